"""Regulated Pure Pursuit path follower, with Nav2's progress and goal checkers.

Pure pursuit steers towards a carrot point one lookahead distance along the path: in the robot
frame the curvature of the arc through the carrot (x, y) is 2y / (x^2 + y^2), and the angular
velocity is the linear velocity times that curvature. Nav2's regulations then slow the robot
down in tight turns (`regulated_linear_scaling_min_radius`), near obstacles (the inflation cost
under the robot, turned back into a distance) and when approaching the goal, and it rotates in
place towards the path or the goal heading when the angle is large.

The regulations are free functions on plain values, as Nav2's `heuristics` namespace; the
controller keeps only the last command (for acceleration limits).
Reference: navigation2 nav2_regulated_pure_pursuit_controller (regulated_pure_pursuit_controller.cpp,
regulation_functions.hpp); nav2_controller's simple_progress_checker and simple_goal_checker.
"""
from __future__ import annotations

import math
import threading
from dataclasses import dataclass, fields
from typing import Callable

import numpy as np

from zros.navigation.costmap import INSCRIBED_INFLATED_OBSTACLE, NO_INFORMATION
from zros.rotations import angle_diff

__all__ = ['RPPParams', 'RegulatedPurePursuit', 'CollisionAhead', 'ProgressChecker', 'GoalChecker',
           'PathFollower', 'FollowError', 'FAILED_TO_MAKE_PROGRESS', 'NO_VALID_CONTROL', 'INVALID_PATH',
           'curvature_constraint', 'cost_constraint', 'approach_velocity', 'late_loop_scale']


@dataclass
class RPPParams:
    """Nav2's RegulatedPurePursuitController parameters zros uses (same names, same defaults)."""

    desired_linear_vel: float = 0.5                 # [m/s]
    lookahead_dist: float = 0.6                     # [m]
    min_lookahead_dist: float = 0.3                 # [m]
    max_lookahead_dist: float = 0.9                 # [m]
    lookahead_time: float = 1.5                     # [s]
    use_velocity_scaled_lookahead_dist: bool = False
    rotate_to_heading_angular_vel: float = 1.8      # [rad/s]
    use_rotate_to_heading: bool = True
    rotate_to_heading_min_angle: float = 0.785      # [rad]
    max_angular_accel: float = 3.2                  # [rad/s^2]
    use_regulated_linear_velocity_scaling: bool = True
    regulated_linear_scaling_min_radius: float = 0.9   # [m]
    regulated_linear_scaling_min_speed: float = 0.25   # [m/s]
    use_cost_regulated_linear_velocity_scaling: bool = True
    cost_scaling_dist: float = 0.6                  # [m]
    cost_scaling_gain: float = 1.0
    inflation_cost_scaling_factor: float = 3.0      # [1/m], the inflation layer's
    min_approach_linear_velocity: float = 0.05      # [m/s]
    approach_velocity_scaling_dist: float = 0.6     # [m]
    use_collision_detection: bool = True
    max_allowed_time_to_collision_up_to_carrot: float = 1.0   # [s]
    max_angular_vel: float = 1.0                    # [rad/s] zros: the robot's limit (burger: 2.84)

    @classmethod
    def names(cls) -> list[str]:
        return [f.name for f in fields(cls)]


# A blocked arc with the carrot within this angle of straight ahead [rad] is a real obstacle.
_ALIGNED_RAD = 0.1


class CollisionAhead(Exception):
    """The commanded arc runs into an obstacle within the collision horizon."""


def curvature_constraint(v: float, curvature: float, min_radius: float) -> float:
    """Slow down in turns tighter than `min_radius` [m], proportionally to the radius."""
    radius = abs(1.0 / curvature) if curvature != 0 else math.inf
    if radius < min_radius:
        return v * (1.0 - abs(radius - min_radius) / min_radius)
    return v


def cost_constraint(v: float, cost: int, *, inscribed_radius: float, cost_scaling_factor: float,
                    cost_scaling_dist: float, cost_scaling_gain: float) -> float:
    """Slow down near obstacles: the inflation cost under the robot, inverted into a distance [m]."""
    if cost == NO_INFORMATION or cost <= 0 or cost >= INSCRIBED_INFLATED_OBSTACLE:
        return v
    distance = -math.log(cost / (INSCRIBED_INFLATED_OBSTACLE - 1)) / cost_scaling_factor + inscribed_radius
    if distance < cost_scaling_dist:
        return v * cost_scaling_gain * distance / cost_scaling_dist
    return v


def approach_velocity(v: float, remaining: float, *, scaling_dist: float, min_velocity: float) -> float:
    """Slow down over the last `scaling_dist` metres of the path, never below `min_velocity`."""
    if remaining < scaling_dist:
        return max(min(v, v * remaining / scaling_dist), min_velocity)
    return v


def late_loop_scale(interval: float, period: float, *, floor: float = 0.25) -> float:
    """How much to slow down when the control loop ran `interval` [s] after its last step instead
    of its `period` [s]: each command is then held longer, so the speed is cut by period /
    interval to keep the distance driven per command (what the collision check looked ahead for)
    as planned; never below `floor`, so a busy machine still makes progress."""
    if not interval > period:
        return 1.0
    return max(floor, period / interval)


class RegulatedPurePursuit:
    """Turns (robot pose, path) into (v, w). Poses are (x, y, yaw) in the path's frame [m, rad]."""

    def __init__(self, params: RPPParams, *, inscribed_radius: float = 0.1, control_period: float = 0.1) -> None:
        self.params = params
        self.inscribed_radius = inscribed_radius
        self.control_period = control_period
        self._last_w = 0.0

    def reset(self) -> None:
        self._last_w = 0.0

    def lookahead(self, speed: float) -> float:
        p = self.params
        if p.use_velocity_scaled_lookahead_dist:
            return float(np.clip(abs(speed) * p.lookahead_time, p.min_lookahead_dist, p.max_lookahead_dist))
        return p.lookahead_dist

    def compute(self, pose: tuple[float, float, float], speed: float, path: np.ndarray, goal_yaw: float, *,
                xy_goal_tolerance: float, cost_at: Callable[[np.ndarray], np.ndarray] | None = None,
                ) -> tuple[float, float]:
        """Velocity command for `pose` following `path` ((N, 2), already pruned to start near the
        robot); `cost_at` maps (M, 2) points in the path frame to costmap costs.

        When the arc to the carrot runs into an obstacle, a carrot at `min_lookahead_dist` is
        tried before giving up (zros's addition to Nav2's controller): in a doorway the long arc
        cuts the jamb's corner where the path itself is clear, and the short one follows the
        path. If that arc is blocked too, the robot turns in place towards the near carrot (a
        round robot can always turn where it stands), after which the way along the path is
        straight ahead; only a robot already facing it raises CollisionAhead."""
        lookahead = self.lookahead(speed)
        near = self.params.min_lookahead_dist
        try:
            return self._command(pose, path, goal_yaw, lookahead, xy_goal_tolerance, cost_at)
        except CollisionAhead as exc:
            blocked = exc
        if near < lookahead:
            try:
                return self._command(pose, path, goal_yaw, near, xy_goal_tolerance, cost_at)
            except CollisionAhead as exc:
                blocked = exc
        carrot = self._carrot(pose, path, min(near, lookahead))[0]
        heading = math.atan2(carrot[1], carrot[0])
        if not self.params.use_rotate_to_heading or abs(heading) < _ALIGNED_RAD:
            raise blocked
        return 0.0, self._rotate(heading)

    @staticmethod
    def _carrot(pose: tuple[float, float, float], path: np.ndarray, lookahead: float) -> tuple[np.ndarray, np.ndarray]:
        """The carrot in the robot frame (the first path point `lookahead` [m] away, else the
        last), and every path point's distance from the robot."""
        x, y, yaw = pose
        c, s = math.cos(yaw), math.sin(yaw)
        rel = path - (x, y)
        local = np.stack([c * rel[:, 0] + s * rel[:, 1], -s * rel[:, 0] + c * rel[:, 1]], axis=1)
        dist = np.hypot(local[:, 0], local[:, 1])
        beyond = np.nonzero(dist >= lookahead)[0]
        return (local[beyond[0]] if len(beyond) else local[-1]), dist

    def _command(self, pose: tuple[float, float, float], path: np.ndarray, goal_yaw: float, lookahead: float,
                 xy_goal_tolerance: float, cost_at: Callable[[np.ndarray], np.ndarray] | None) -> tuple[float, float]:
        """compute() with a given lookahead [m]."""
        p = self.params
        x, y, yaw = pose
        carrot, dist = self._carrot(pose, path, lookahead)
        seg = np.linalg.norm(np.diff(path, axis=0), axis=1)
        remaining = float(dist[0] + seg.sum())
        goal_dist = float(dist[-1])
        if p.use_rotate_to_heading and goal_dist < xy_goal_tolerance:
            return 0.0, self._rotate(angle_diff(goal_yaw, yaw))
        heading = math.atan2(carrot[1], carrot[0])
        if p.use_rotate_to_heading and abs(heading) > p.rotate_to_heading_min_angle:
            return 0.0, self._rotate(heading)
        d2 = float(carrot @ carrot)
        curvature = 2.0 * carrot[1] / d2 if d2 > 1e-9 else 0.0
        v = p.desired_linear_vel
        if p.use_regulated_linear_velocity_scaling:
            v = curvature_constraint(v, curvature, p.regulated_linear_scaling_min_radius)
        if p.use_cost_regulated_linear_velocity_scaling and cost_at is not None:
            cost = int(cost_at(np.array([[x, y]]))[0])
            v = min(v, cost_constraint(p.desired_linear_vel, cost, inscribed_radius=self.inscribed_radius,
                                       cost_scaling_factor=p.inflation_cost_scaling_factor,
                                       cost_scaling_dist=p.cost_scaling_dist, cost_scaling_gain=p.cost_scaling_gain))
        if p.use_regulated_linear_velocity_scaling or p.use_cost_regulated_linear_velocity_scaling:
            v = max(v, p.regulated_linear_scaling_min_speed)
        v = approach_velocity(v, remaining, scaling_dist=p.approach_velocity_scaling_dist,
                              min_velocity=p.min_approach_linear_velocity)
        v = min(v, p.desired_linear_vel)
        w = v * curvature
        if abs(w) > p.max_angular_vel:
            v *= p.max_angular_vel / abs(w)
            w = math.copysign(p.max_angular_vel, w)
        if p.use_collision_detection and cost_at is not None:
            self._check_collision(pose, v, w, math.sqrt(d2), cost_at)
        self._last_w = w
        return v, w

    def _rotate(self, angle: float) -> float:
        p = self.params
        target = math.copysign(p.rotate_to_heading_angular_vel, angle)
        # Do not overshoot: the speed that stops exactly at the target angle at max decel.
        target = math.copysign(min(abs(target), math.sqrt(2 * p.max_angular_accel * abs(angle)) + 0.05), angle)
        step = p.max_angular_accel * self.control_period
        w = float(np.clip(target, self._last_w - step, self._last_w + step))
        w = float(np.clip(w, -p.max_angular_vel, p.max_angular_vel))
        self._last_w = w
        return w

    def _check_collision(self, pose: tuple[float, float, float], v: float, w: float, carrot_dist: float,
                         cost_at: Callable[[np.ndarray], np.ndarray]) -> None:
        """Project the arc forward up to the carrot (at most max_allowed_time_to_collision_up_to_carrot)
        and refuse it if the robot's centre would enter an inscribed or lethal cell."""
        if abs(v) < 1e-3:
            return
        horizon = min(self.params.max_allowed_time_to_collision_up_to_carrot, carrot_dist / abs(v))
        t = np.linspace(0.05, max(horizon, 0.05), 12)
        x, y, yaw = pose
        if abs(w) < 1e-6:
            px, py = x + v * t * math.cos(yaw), y + v * t * math.sin(yaw)
        else:
            r = v / w
            px = x + r * (np.sin(yaw + w * t) - math.sin(yaw))
            py = y - r * (np.cos(yaw + w * t) - math.cos(yaw))
        costs = cost_at(np.stack([px, py], axis=1))
        blocked = (costs >= INSCRIBED_INFLATED_OBSTACLE) & (costs != NO_INFORMATION)
        if blocked.any() and int(cost_at(np.array([[x, y]]))[0]) < INSCRIBED_INFLATED_OBSTACLE:
            raise CollisionAhead('RegulatedPurePursuitController detected collision ahead!')


@dataclass
class ProgressChecker:
    """nav2_controller::SimpleProgressChecker: the robot must move `required_movement_radius` [m]
    within `movement_time_allowance` [s], or it is stuck."""

    required_movement_radius: float = 0.5
    movement_time_allowance: float = 10.0
    _baseline: tuple[float, float, float] | None = None

    def reset(self) -> None:
        self._baseline = None

    def check(self, x: float, y: float, now: float) -> bool:
        """True while progress is fine; `now` is the node clock [s]."""
        if self._baseline is None or math.hypot(x - self._baseline[0], y - self._baseline[1]) > self.required_movement_radius:
            self._baseline = (x, y, now)
            return True
        return now - self._baseline[2] <= self.movement_time_allowance


@dataclass
class GoalChecker:
    """nav2_controller::SimpleGoalChecker (stateful): once within `xy_goal_tolerance` [m] the position
    counts as reached for good, and only the heading (`yaw_goal_tolerance` [rad]) is left."""

    xy_goal_tolerance: float = 0.25
    yaw_goal_tolerance: float = 0.25
    stateful: bool = True
    _xy_reached: bool = False

    def reset(self) -> None:
        self._xy_reached = False

    @property
    def xy_reached(self) -> bool:
        """The position counts as reached for good (stateful) and only the heading is left."""
        return self._xy_reached

    def is_goal_reached(self, pose: tuple[float, float, float], goal: tuple[float, float, float]) -> bool:
        if not self._xy_reached:
            if math.hypot(pose[0] - goal[0], pose[1] - goal[1]) > self.xy_goal_tolerance:
                return False
            self._xy_reached = self.stateful
        return abs(angle_diff(pose[2], goal[2])) <= self.yaw_goal_tolerance


# nav2_msgs/action/FollowPath result codes.
FOLLOW_UNKNOWN = 100
INVALID_PATH = 103
FAILED_TO_MAKE_PROGRESS = 105
NO_VALID_CONTROL = 106


class FollowError(Exception):
    """Following stopped; `code` is the FollowPath error code."""

    def __init__(self, code: int, message: str) -> None:
        super().__init__(message)
        self.code = code


class PathFollower:
    """One FollowPath goal's state: the path, how far along it the robot is, the checkers.

    `step` is what controller_server does each control period (computeControl): prune the path
    behind the robot, check the goal, check progress, ask the controller for a command.

    `failure_tolerance` [s] is controller_server's: a controller that cannot find a command (a
    collision ahead) stops the robot and is asked again next period; only when it has failed for
    longer than this does the goal fail (0: at the first failure, -1: never). A step that comes
    late (more than 1.5 control periods after the last one: a busy machine) slows the command
    by `late_loop_scale`, so the robot slows down instead of driving blind for longer.

    A new goal's `set_path` comes from another thread than the running goal's `step`: both hold
    `lock` (re-entrant), so a step never sees half of a new path. A caller that must check
    something first (is my goal still the current one?) holds `lock` around the check and the step.
    """

    def __init__(self, controller: RegulatedPurePursuit, goal_checker: GoalChecker,
                 progress_checker: ProgressChecker, *, prune_distance: float = 1.0,
                 failure_tolerance: float = 0.0) -> None:
        self.controller = controller
        self.goal_checker = goal_checker
        self.progress_checker = progress_checker
        self.prune_distance = prune_distance
        self.failure_tolerance = failure_tolerance
        self.path = np.zeros((0, 2))
        self.goal = (0.0, 0.0, 0.0)
        self._closest = 0
        self._last_step: float | None = None         # node clock [s] of the last step
        self._last_valid: float | None = None        # ... of the last step with a valid command
        self.lock = threading.RLock()

    def set_path(self, path: np.ndarray, goal_yaw: float, *, keep_progress: bool = False) -> None:
        """A new path; `keep_progress` for a replanned path of the same goal (Nav2 keeps the checkers)."""
        path = np.asarray(path, np.float64).reshape(-1, 2)
        if len(path) == 0:
            raise FollowError(INVALID_PATH, 'Path is empty.')
        with self.lock:
            self._set_path(path, goal_yaw, keep_progress)

    def _set_path(self, path: np.ndarray, goal_yaw: float, keep_progress: bool) -> None:
        self.path = path
        self.goal = (float(path[-1, 0]), float(path[-1, 1]), float(goal_yaw))
        self._closest = 0
        if not keep_progress:
            self.controller.reset()
            self.goal_checker.reset()
            self.progress_checker.reset()
            self._last_step = self._last_valid = None

    def remaining_distance(self, x: float, y: float) -> float:
        with self.lock:
            rest = self.path[self._closest:]
        seg = np.linalg.norm(np.diff(rest, axis=0), axis=1).sum() if len(rest) > 1 else 0.0
        return float(math.hypot(rest[0, 0] - x, rest[0, 1] - y) + seg)

    def step(self, pose: tuple[float, float, float], speed: float, now: float,
             cost_at: Callable[[np.ndarray], np.ndarray] | None = None) -> tuple[float, float] | None:
        """Command for this period, or None once the goal is reached; FollowError when stuck."""
        with self.lock:
            return self._step(pose, speed, now, cost_at)

    def _step(self, pose: tuple[float, float, float], speed: float, now: float,
              cost_at: Callable[[np.ndarray], np.ndarray] | None) -> tuple[float, float] | None:
        x, y, _ = pose
        if self.goal_checker.is_goal_reached(pose, self.goal):
            return None
        if not self.progress_checker.check(x, y, now):
            raise FollowError(FAILED_TO_MAKE_PROGRESS, 'Failed to make progress')
        # Closest point from the last one on, within prune_distance of path length ahead.
        rest = self.path[self._closest:]
        along = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(rest, axis=0), axis=1))])
        window = rest[along <= self.prune_distance + 1e-9]
        self._closest += int(np.argmin(np.hypot(window[:, 0] - x, window[:, 1] - y)))
        # Once the stateful checker has the position, only the heading is left: rotate to it even
        # if localisation noise puts the robot a hair outside the tolerance again (else it turns
        # back towards the goal point, then to the heading, and so on).
        tolerance = math.inf if self.goal_checker.xy_reached else self.goal_checker.xy_goal_tolerance
        period = self.controller.control_period
        interval = period if self._last_step is None else now - self._last_step
        self._last_step = now
        if self._last_valid is None:
            self._last_valid = now
        try:
            v, w = self.controller.compute(pose, speed, self.path[self._closest:], self.goal[2],
                                           xy_goal_tolerance=tolerance, cost_at=cost_at)
        except CollisionAhead as exc:
            patience = self.failure_tolerance
            if patience == 0.0 or (patience > 0.0 and now - self._last_valid > patience):
                raise FollowError(NO_VALID_CONTROL, str(exc) if patience == 0.0 else
                                  f'{exc} Controller patience exceeded') from None
            self.controller.reset()
            return 0.0, 0.0
        self._last_valid = now
        if interval > 1.5 * period:
            scale = late_loop_scale(interval, period)
            return v * scale, w * scale
        return v, w
