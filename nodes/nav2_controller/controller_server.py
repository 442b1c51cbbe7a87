"""nav2_controller's controller_server: `follow_path` with Regulated Pure Pursuit on the local
costmap (which runs in this process as /local_costmap/local_costmap), publishing `cmd_vel`.

    zros run nav2_controller controller_server --ros-args --params-file burger.yaml

A lifecycle node. Parameters as Nav2's: `controller_frequency`, `controller_plugins`
(`FollowPath`), `FollowPath.<RPP parameter>` (desired_linear_vel, lookahead_dist, ...),
`progress_checker_plugin(s)` with `required_movement_radius` / `movement_time_allowance`,
`goal_checker_plugins` with `xy_goal_tolerance` / `yaw_goal_tolerance` / `stateful`, `odom_topic`,
`failure_tolerance` (seconds a controller may fail, stopping the robot, before the goal aborts).
A FollowPath plugin other than Regulated Pure Pursuit (TurtleBot3's files name DWB) is served
by Regulated Pure Pursuit, with DWB's `max_vel_x` / `max_vel_theta` as its speeds, and said so.

On a busy machine the loop warns when it misses its rate, as Nav2's does, and a step that
comes late slows the command in proportion (zros.navigation.controller.late_loop_scale): the
robot slows down rather than holding each command for longer at full speed.

A new goal replaces the running one (which ends ABORTED), keeping the goal and progress
checkers when it leads to the same place: that is how the navigator hands over replanned paths.
Failures abort with FollowPath's error codes (FAILED_TO_MAKE_PROGRESS, NO_VALID_CONTROL, TF_ERROR).
"""
from __future__ import annotations

import math
import sys
from typing import Any

import numpy as np

import zros
from zros.executors import ExternalShutdownException, spin_nodes
from zros.lifecycle import LifecycleNode, State, TransitionCallbackReturn
from zros.navigation.controller import (FollowError, GoalChecker, PathFollower, ProgressChecker, RegulatedPurePursuit,
                                        RPPParams)
from zros.navigation.costmap_ros import CostmapNode
from zros.navigation.node_support import Nav2Params, lookup_pose, path_points
from zros.navigation.servers import GoalRunner, gated_action_server, RESULT_TIMEOUT_S
from zros.tf2_ros import Buffer, TransformListener

from interfaces.geometry_msgs.msg import Twist
from interfaces.nav2_msgs.action import FollowPath
from interfaces.nav_msgs.msg import Odometry

_TF_ERROR = 102
_SAME_GOAL_M = 0.05


class ControllerServer(LifecycleNode):
    def __init__(self) -> None:
        super().__init__('controller_server')
        self.tf_buffer = Buffer(node=self)
        self.tf_listener = TransformListener(self.tf_buffer, self)
        prm = Nav2Params(self)
        self.frequency = prm.get('controller_frequency', 20.0)
        failure_tolerance = prm.get('failure_tolerance', 0.0)
        self.controller_ids = prm.get('controller_plugins', ['FollowPath'])
        cid = self.controller_ids[0]
        plugin = prm.get(f'{cid}.plugin', 'nav2_regulated_pure_pursuit_controller::RegulatedPurePursuitController')
        rpp = RPPParams()
        for name in RPPParams.names():
            setattr(rpp, name, prm.get(f'{cid}.{name}', getattr(rpp, name)))
        if 'RegulatedPurePursuit' not in plugin:
            rpp.desired_linear_vel = prm.get(f'{cid}.max_vel_x', 0.22)
            rpp.max_angular_vel = prm.get(f'{cid}.max_vel_theta', 1.0)
            self.get_logger().info(f'{cid}: {plugin} is not implemented in zros; following paths with Regulated '
                                   f'Pure Pursuit at max_vel_x {rpp.desired_linear_vel} m/s')
        rpp.max_angular_vel = prm.get(f'{cid}.max_angular_vel', rpp.max_angular_vel)
        progress_id = prm.get('progress_checker_plugin', 'progress_checker')
        if self.has_parameter('progress_checker_plugins') or 'progress_checker_plugins' in self._parameter_overrides:
            progress_id = (prm.get('progress_checker_plugins', [progress_id]) or [progress_id])[0]
        goal_id = (prm.get('goal_checker_plugins', ['general_goal_checker']) or ['general_goal_checker'])[0]
        if 'goal_checker_plugin' in self._parameter_overrides:
            goal_id = prm.get('goal_checker_plugin', goal_id)
        self.progress = ProgressChecker(prm.get(f'{progress_id}.required_movement_radius', 0.5),
                                        prm.get(f'{progress_id}.movement_time_allowance', 10.0))
        self.goal_checker = GoalChecker(prm.get(f'{goal_id}.xy_goal_tolerance', 0.25),
                                        prm.get(f'{goal_id}.yaw_goal_tolerance', 0.25),
                                        prm.get(f'{goal_id}.stateful', True))
        prm.get(f'{progress_id}.plugin', 'nav2_controller::SimpleProgressChecker')
        prm.get(f'{goal_id}.plugin', 'nav2_controller::SimpleGoalChecker')
        odom_topic = prm.get('odom_topic', 'odom')
        self.robot_base_frame = 'base_link'
        result_timeout = prm.get('action_server_result_timeout', RESULT_TIMEOUT_S)
        prm.report_unused()
        self.costmap = CostmapNode('local_costmap', default_frame='odom', rolling=True, tf_buffer=self.tf_buffer)
        self.robot_base_frame = self.costmap.robot_base_frame
        self.follower = PathFollower(RegulatedPurePursuit(rpp, inscribed_radius=self.costmap.params.robot_radius,
                                                          control_period=1.0 / self.frequency),
                                     self.goal_checker, self.progress, failure_tolerance=failure_tolerance)
        self.speed = 0.0
        self.goals = GoalRunner(self, stop=self._stop)
        self.cmd_pub = self.create_lifecycle_publisher(Twist, 'cmd_vel', 1)
        self.create_subscription(Odometry, odom_topic, self._on_odom, 10)
        gated_action_server(self, FollowPath, 'follow_path', self._follow, result_timeout=result_timeout)

    def on_deactivate(self, state: State) -> TransitionCallbackReturn:
        self._stop()
        return super().on_deactivate(state)

    def _on_odom(self, msg: Any) -> None:
        self.speed = msg.twist.twist.linear.x

    def _stop(self) -> None:
        if self.current_state.label == 'active':
            self.cmd_pub.publish(Twist())

    # -- the goal loop -----------------------------------------------------------------------
    def _follow(self, handle: Any) -> Any:
        goal = handle.request
        result = FollowPath.Result()
        previous = self.goals.slot.take(handle)
        if goal.controller_id and goal.controller_id not in self.controller_ids:
            return self.goals.fail(handle, result, 101, f'FollowPath called with controller name {goal.controller_id}, '
                                                   'which does not exist')
        if not goal.path.poses:
            return self.goals.fail(handle, result, 103, 'Path is empty.')
        path, goal_yaw = path_points(goal.path)
        path_frame = goal.path.header.frame_id or 'map'
        with self.follower.lock:   # the preempted goal's loop may be in a step (see step below)
            same_goal = (previous is not None and self.follower.path.size
                         and np.hypot(*(self.follower.path[-1] - path[-1])) < _SAME_GOAL_M)
            self.follower.set_path(path, goal_yaw, keep_progress=bool(same_goal))
        feedback = FollowPath.Feedback()

        def step() -> Any:
            if self.current_state.label != 'active':
                return self.goals.fail(handle, result, 100, 'controller_server is not active')
            try:
                pose = lookup_pose(self.tf_buffer, path_frame, self.robot_base_frame)
                local = lookup_pose(self.tf_buffer, self.costmap.global_frame, self.robot_base_frame)
            except Exception as exc:  # noqa: BLE001 - tf2's exceptions
                return self.goals.fail(handle, result, _TF_ERROR, f'Unable to transform robot pose into {path_frame}: {exc}')
            now = self.get_clock().now().nanoseconds / 1e9
            with self.follower.lock:
                # A newer goal has taken the slot and set (or is setting) its path: this goal's
                # last step must not run on it; the loop ends this goal as preempted.
                if not self.goals.slot.is_current(handle):
                    return None
                try:
                    cmd = self.follower.step(pose, self.speed, now, _cost_in(self.costmap, pose, local))
                    distance = self.follower.remaining_distance(pose[0], pose[1])
                except FollowError as exc:
                    return self.goals.fail(handle, result, exc.code, str(exc))
            if cmd is None:
                self._stop()
                self.get_logger().info('Reached the goal!')
                handle.succeed()
                return result
            twist = Twist()
            twist.linear.x, twist.angular.z = float(cmd[0]), float(cmd[1])
            self.cmd_pub.publish(twist)
            feedback.speed = float(self.speed)
            feedback.distance_to_goal = float(distance)
            handle.publish_feedback(feedback)
            return None
        return self.goals.loop(handle, result, self.frequency, step, report_missed_rate=True)


def _cost_in(costmap: CostmapNode, pose: tuple, local: tuple) -> Any:
    """cost_at for points in the path's frame: mapped into the costmap's frame through the robot,
    whose pose is known in both."""
    dyaw = local[2] - pose[2]
    c, s = math.cos(dyaw), math.sin(dyaw)

    def cost_at(points: np.ndarray) -> np.ndarray:
        rel = np.asarray(points, np.float64) - pose[:2]
        moved = np.stack([local[0] + c * rel[:, 0] - s * rel[:, 1], local[1] + s * rel[:, 0] + c * rel[:, 1]], axis=1)
        return costmap.cost_at(moved)
    return cost_at


def main(args: list[str] | None = None) -> int:
    try:
        with zros.init(args=args):
            node = ControllerServer()
            spin_nodes(node, node.costmap)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    return 0


if __name__ == '__main__':
    sys.exit(main())
