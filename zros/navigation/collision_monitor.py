"""Collision monitoring: nav2_collision_monitor's zones and the velocity they allow, as plain numpy.

The last safety layer between the navigation and the robot: each velocity command is checked
against the latest obstacle points (laser hits, in the robot's base frame) and zones around the
robot, in the order they are listed:

* `stop`: `min_points` or more points inside the zone: the robot stops (nothing overrides it);
* `slowdown`: the command is scaled by `slowdown_ratio`;
* `limit`: the command is scaled so that the linear speed is at most `linear_limit` [m/s] and
  the turn rate at most `angular_limit` [rad/s] (one ratio for both, keeping the curvature);
* `approach`: the robot's motion under the command is simulated for `time_before_collision` [s]
  in steps of `simulation_time_step` [s]; if the zone (the footprint) would then hold
  `min_points` points after t seconds, the command is scaled by t / time_before_collision, so the
  robot slows down as it nears an obstacle and stops at it.

Of several zones that act, the slowest resulting command wins (by vx² + vy² + wz², as Nav2
orders velocities). A zone is a polygon (`points`,
(K, 2) vertices [m] in the base frame) or a circle (`radius` [m] about the base frame's origin).
Velocities are (vx [m/s], vy [m/s], wz [rad/s]).

Reference: navigation2 nav2_collision_monitor (collision_monitor_node.cpp, polygon.cpp,
circle.cpp) and its configuration guide.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

__all__ = ['ACTIONS', 'ZONE_PARAMETERS', 'Zone', 'Decision', 'points_in_polygon', 'scan_points', 'decide']

# nav2_msgs/msg/CollisionMonitorState action_type values.
ACTIONS = {'do_nothing': 0, 'stop': 1, 'slowdown': 2, 'approach': 3, 'limit': 4}
#: A zone's parameters that map one to one onto `Zone`'s fields of the same name (its defaults
#: are Nav2's): what a parameter file may set under the zone's name besides its shape.
ZONE_PARAMETERS = ('min_points', 'slowdown_ratio', 'linear_limit', 'angular_limit', 'time_before_collision',
                   'simulation_time_step', 'enabled')


def points_in_polygon(points: np.ndarray, vertices: np.ndarray) -> np.ndarray:
    """(N,) bool: which of the (N, 2) points lie inside the polygon of (K, 2) vertices (even-odd
    rule, all points and edges at once)."""
    points = np.asarray(points, np.float64).reshape(-1, 2)
    a = np.asarray(vertices, np.float64)
    b = np.roll(a, -1, axis=0)
    px, py = points[:, :1], points[:, 1:]                                  # (N, 1) against (K,) edges
    straddles = (a[:, 1] > py) != (b[:, 1] > py)
    with np.errstate(divide='ignore', invalid='ignore'):
        x_cross = a[:, 0] + (py - a[:, 1]) * (b[:, 0] - a[:, 0]) / (b[:, 1] - a[:, 1])
    crossings = straddles & (px < x_cross)
    return (crossings.sum(axis=1) % 2) == 1


def scan_points(ranges: np.ndarray, angle_min: float, angle_increment: float, range_min: float,
                range_max: float) -> np.ndarray:
    """(M, 2) points [m] in the scanner's frame of a LaserScan's valid returns (finite, within
    [range_min, range_max]); angles [rad] counter-clockwise from the scanner's x axis."""
    ranges = np.asarray(ranges, np.float64)
    angles = angle_min + angle_increment * np.arange(len(ranges))
    ok = np.isfinite(ranges) & (ranges >= range_min) & (ranges <= range_max)
    return np.stack([ranges[ok] * np.cos(angles[ok]), ranges[ok] * np.sin(angles[ok])], axis=1)


@dataclass
class Zone:
    """One of Nav2's collision monitor polygons (names and defaults as Nav2 Jazzy's)."""

    name: str
    action_type: str                       # 'stop', 'slowdown', 'limit' or 'approach'
    vertices: np.ndarray | None = None     # (K, 2) [m] in the base frame, for type 'polygon'
    radius: float | None = None            # [m], for type 'circle'
    min_points: int = 4
    slowdown_ratio: float = 0.5
    linear_limit: float = 0.5              # [m/s]
    angular_limit: float = 0.5             # [rad/s]
    time_before_collision: float = 2.0     # [s]
    simulation_time_step: float = 0.1      # [s]
    enabled: bool = True

    def __post_init__(self) -> None:
        if self.action_type not in ACTIONS or self.action_type == 'do_nothing':
            raise ValueError(f'{self.name}: unknown action_type {self.action_type!r} '
                             '(stop, slowdown, limit or approach)')
        if self.radius is None and self.vertices is not None and len(self.vertices) < 3:
            raise ValueError(f'{self.name}: a polygon needs at least 3 points, got {len(self.vertices)}')

    @property
    def has_shape(self) -> bool:
        """False until a footprint taken from a topic has arrived."""
        return self.radius is not None or self.vertices is not None

    def inside(self, points: np.ndarray) -> np.ndarray:
        """(N,) bool: which (N, 2) base-frame points are in the zone."""
        points = np.asarray(points, np.float64).reshape(-1, 2)
        if self.radius is not None:
            return np.hypot(points[:, 0], points[:, 1]) <= self.radius
        return points_in_polygon(points, self.vertices)

    def triggered(self, points: np.ndarray) -> bool:
        return int(self.inside(points).sum()) >= self.min_points

    def collision_time(self, points: np.ndarray, velocity: np.ndarray) -> float | None:
        """Seconds [s] until the zone, carried along by `velocity`, holds `min_points` points;
        None if not within `time_before_collision`.

        Counted as Nav2's Polygon::getCollisionTime counts it: the clock reads 0 after the first
        simulated step and the simulation runs to `time_before_collision` inclusive, so a contact
        one step ahead stops the robot (ratio 0) rather than letting it creep on at one step's
        share of the command."""
        if self.triggered(points):
            return 0.0
        points = np.asarray(points, np.float64).reshape(-1, 2)
        vx, vy, wz = velocity
        x = y = theta = 0.0
        dt = self.simulation_time_step
        steps = int(np.floor(self.time_before_collision / dt + 1e-9)) + 1
        for step in range(steps):
            x += (vx * np.cos(theta) - vy * np.sin(theta)) * dt
            y += (vx * np.sin(theta) + vy * np.cos(theta)) * dt
            theta += wz * dt
            c, s = np.cos(theta), np.sin(theta)
            rel = points - (x, y)
            moved = np.stack([c * rel[:, 0] + s * rel[:, 1], -s * rel[:, 0] + c * rel[:, 1]], axis=1)
            if self.triggered(moved):
                return step * dt
        return None


class Decision(NamedTuple):
    """What the monitor does with a command: the action (a key of ACTIONS), the zone that
    decided it ('' when none acted) and the (3,) velocity to send."""

    action: str
    polygon_name: str
    velocity: np.ndarray


def decide(zones: list[Zone], points: np.ndarray, velocity: np.ndarray) -> Decision:
    """The command the robot may follow, given obstacle `points` ((N, 2) [m], base frame) and the
    commanded `velocity` (3,)."""
    velocity = np.asarray(velocity, np.float64)
    best = Decision('do_nothing', '', velocity)
    for zone in zones:
        if not zone.enabled or not zone.has_shape:
            continue
        if zone.action_type == 'approach':
            t = zone.collision_time(points, velocity)
            if t is None:
                continue
            safe = velocity * (t / zone.time_before_collision)
        elif not zone.triggered(points):
            continue
        elif zone.action_type == 'stop':
            return Decision('stop', zone.name, np.zeros(3))
        elif zone.action_type == 'slowdown':
            safe = velocity * zone.slowdown_ratio
        else:
            safe = _limited(velocity, zone.linear_limit, zone.angular_limit)
        if _slower(safe, best.velocity):
            best = Decision(zone.action_type, zone.name, safe)
    return best


def _limited(velocity: np.ndarray, linear_limit: float, angular_limit: float) -> np.ndarray:
    """The command scaled by one ratio that brings both speeds within their limits (Jazzy's rule:
    the same ratio on every component keeps the path's curvature, so a limited robot still
    follows the arc the controller chose)."""
    linear = float(np.hypot(velocity[0], velocity[1]))
    ratio = 1.0
    if linear > 0.0:
        ratio = min(ratio, linear_limit / linear)
    if velocity[2] != 0.0:
        ratio = min(ratio, angular_limit / abs(float(velocity[2])))
    return velocity * min(max(ratio, 0.0), 1.0)


def _slower(a: np.ndarray, b: np.ndarray) -> bool:
    """Nav2's Velocity ordering: by vx² + vy² + wz², so a turn in place counts as motion."""
    return bool(np.dot(a, a) < np.dot(b, b))
