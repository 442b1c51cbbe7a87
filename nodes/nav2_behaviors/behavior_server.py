"""nav2_behaviors' behavior_server: the `spin`, `backup`, `drive_on_heading`, `wait` and
`assisted_teleop` actions.

    zros run nav2_behaviors behavior_server --ros-args --params-file burger.yaml

A lifecycle node. Parameters as Nav2's: `cycle_frequency`, `local_frame` (odom),
`robot_base_frame`, `simulate_ahead_time` (collision look-ahead), `max_rotational_vel`,
`min_rotational_vel`, `rotational_acc_lim`. Motion is measured in `local_frame` through TF and
checked ahead against the local costmap (`local_costmap/costmap_raw`); a motion that would hit
something stops with COLLISION_AHEAD, one that runs out of `time_allowance` with TIMEOUT.
BackUp drives backwards whatever the signs of its distance and speed, as Nav2's.
AssistedTeleop passes `cmd_vel_teleop` on to `cmd_vel`, slowed before a collision
(zros.navigation.assisted_teleop; `projection_time`, `simulation_time_step`), until a message on
`preempt_teleop` ends it (succeeded) or `time_allowance` runs out (TIMEOUT; 0 means no limit).
"""
from __future__ import annotations

import math
import sys
import threading
from typing import Any, Callable

import numpy as np

import zros
from zros.executors import ExternalShutdownException, spin_nodes
from zros.lifecycle import LifecycleNode
from zros.navigation.assisted_teleop import collision_scale, projected_poses
from zros.navigation.costmap import INSCRIBED_INFLATED_OBSTACLE, NO_INFORMATION
from zros.navigation.costmap_ros import CostmapSubscriber
from zros.navigation.node_support import Nav2Params, duration_msg, lookup_pose
from zros.navigation.servers import GoalRunner, gated_action_server, RESULT_TIMEOUT_S
from zros.rotations import angle_diff
from zros.tf2_ros import Buffer, TransformListener

from interfaces.geometry_msgs.msg import Twist
from interfaces.nav2_msgs.action import AssistedTeleop, BackUp, DriveOnHeading, Spin, Wait
from interfaces.std_msgs.msg import Empty


class BehaviorServer(LifecycleNode):
    def __init__(self) -> None:
        super().__init__('behavior_server')
        self.tf_buffer = Buffer(node=self)
        self.tf_listener = TransformListener(self.tf_buffer, self)
        prm = Nav2Params(self)
        self.frequency = prm.get('cycle_frequency', 10.0)
        self.local_frame = prm.get('local_frame', prm.get('global_frame', 'odom'))
        self.robot_base_frame = prm.get('robot_base_frame', 'base_link')
        self.simulate_ahead_time = prm.get('simulate_ahead_time', 2.0)
        self.max_rot = prm.get('max_rotational_vel', 1.0)
        self.min_rot = prm.get('min_rotational_vel', 0.4)
        self.rot_acc = prm.get('rotational_acc_lim', 3.2)
        topic = prm.get('costmap_topic', 'local_costmap/costmap_raw')
        self.projection_time = prm.get('projection_time', 1.0)
        self.simulation_time_step = prm.get('simulation_time_step', 0.1)
        teleop_topic = prm.get('cmd_vel_teleop', 'cmd_vel_teleop')
        prm.get('behavior_plugins', ['spin', 'backup', 'drive_on_heading', 'assisted_teleop', 'wait'])
        result_timeout = prm.get('action_server_result_timeout', RESULT_TIMEOUT_S)
        prm.report_unused()
        self.goals = GoalRunner(self, stop=self._stop)
        self.cmd_pub = self.create_lifecycle_publisher(Twist, 'cmd_vel', 1)
        self.costmap = CostmapSubscriber(self, topic)
        gated_action_server(self, Spin, 'spin', self._spin, result_timeout=result_timeout)
        gated_action_server(self, BackUp, 'backup', lambda h: self._drive(h, BackUp, backwards=True),
                            result_timeout=result_timeout)
        gated_action_server(self, DriveOnHeading, 'drive_on_heading', lambda h: self._drive(h, DriveOnHeading),
                            result_timeout=result_timeout)
        gated_action_server(self, Wait, 'wait', self._wait, result_timeout=result_timeout)
        self._teleop = (0.0, 0.0, 0.0)
        self._preempt = threading.Event()
        self.create_subscription(Twist, teleop_topic, self._on_teleop, 10)
        self.create_subscription(Empty, 'preempt_teleop', lambda _: self._preempt.set(), 10)
        gated_action_server(self, AssistedTeleop, 'assisted_teleop', self._assisted_teleop,
                            result_timeout=result_timeout)

    def _on_teleop(self, msg: Any) -> None:
        self._teleop = (msg.linear.x, msg.linear.y, msg.angular.z)

    def _blocked(self, points: np.ndarray) -> bool:
        """True if any (N, 2) point of `local_frame` is in an inscribed or lethal cell."""
        return bool(self._blocked_each(points).any())

    def _blocked_each(self, points: np.ndarray) -> np.ndarray:
        """Per (N, 2) point of `local_frame`: in an inscribed or lethal cell (False off the map
        or without a costmap)."""
        costs = self.costmap.cost_at(points) if self.costmap.frame_id in ('', self.local_frame) else None
        if costs is None:
            return np.zeros(len(points), bool)
        return (costs >= INSCRIBED_INFLATED_OBSTACLE) & (costs != NO_INFORMATION)

    def _pose(self) -> tuple[float, float, float]:
        return lookup_pose(self.tf_buffer, self.local_frame, self.robot_base_frame)

    def _loop(self, handle: Any, result: Any, allowance: Any, cycle: Callable[[float], tuple[float, float] | None],
              error_base: int) -> Any:
        """Run `cycle(elapsed)` each period until it returns None (done); it returns (v, w) to
        command, and raises _Abort to fail."""
        self.goals.slot.take(handle)
        start = self.get_clock().now()
        limit = allowance.sec + allowance.nanosec / 1e9 if allowance is not None else math.inf

        def step() -> Any:
            elapsed = (self.get_clock().now() - start).nanoseconds / 1e9
            result.total_elapsed_time = duration_msg(elapsed)
            if limit > 0 and elapsed > limit:
                return self.goals.fail(handle, result, error_base + 1, 'Exceeded time allowance before reaching the goal')
            try:
                cmd = cycle(elapsed)
            except _Abort as exc:
                return self.goals.fail(handle, result, error_base + exc.offset, str(exc))
            except Exception as exc:  # noqa: BLE001 - tf2's exceptions
                return self.goals.fail(handle, result, error_base + 2, f'Could not get the robot pose: {exc}')
            if cmd is None:
                self._stop()
                handle.succeed()
                return result
            twist = Twist()
            twist.linear.x, twist.angular.z = cmd
            self.cmd_pub.publish(twist)
            return None
        return self.goals.loop(handle, result, self.frequency, step)

    def _stop(self) -> None:
        if self.current_state.label == 'active':
            self.cmd_pub.publish(Twist())

    # -- behaviours --------------------------------------------------------------------------
    def _spin(self, handle: Any) -> Any:
        goal = handle.request
        target = float(goal.target_yaw)
        state = {'last': None, 'turned': 0.0}
        feedback = Spin.Feedback()
        self.get_logger().info(f'Turning {target:.2f} for spin behavior.')

        def cycle(elapsed: float) -> tuple[float, float] | None:
            _, _, yaw = self._pose()
            if state['last'] is not None:
                state['turned'] += abs(angle_diff(yaw, state['last']))
            state['last'] = yaw
            feedback.angular_distance_traveled = state['turned']
            handle.publish_feedback(feedback)
            left = abs(target) - state['turned']
            if left <= 0.01:
                return None
            w = min(self.max_rot, max(self.min_rot, math.sqrt(2 * self.rot_acc * left)))
            return 0.0, math.copysign(w, target)    # a round robot turning in place hits nothing
        return self._loop(handle, Spin.Result(), goal.time_allowance, cycle, 700)

    def _drive(self, handle: Any, action: Any, backwards: bool = False) -> Any:
        goal = handle.request
        distance = math.hypot(goal.target.x, goal.target.y)
        speed = abs(goal.speed) if backwards else goal.speed
        if distance <= 0 or speed == 0:
            result = action.Result()
            base = 710 if backwards else 720
            return self.goals.fail(handle, result, base + (3 if backwards else 4), 'DriveOnHeading/BackUp: invalid distance or speed')
        sign = -1.0 if backwards else math.copysign(1.0, goal.speed)
        state = {'start': None}
        feedback = action.Feedback()

        def cycle(elapsed: float) -> tuple[float, float] | None:
            x, y, yaw = self._pose()
            if state['start'] is None:
                state['start'] = (x, y)
            travelled = math.hypot(x - state['start'][0], y - state['start'][1])
            feedback.distance_traveled = travelled
            handle.publish_feedback(feedback)
            if travelled >= distance:
                return None
            v = sign * abs(speed)
            ahead = np.linspace(0.05, self.simulate_ahead_time, 8) * v
            pts = np.stack([x + ahead * math.cos(yaw), y + ahead * math.sin(yaw)], axis=1)
            if self._blocked(pts):
                raise _Abort(4 if backwards else 3, 'Collision Ahead - Exiting DriveOnHeading')
            return v, 0.0
        return self._loop(handle, action.Result(), goal.time_allowance, cycle, 710 if backwards else 720)

    def _wait(self, handle: Any) -> Any:
        goal = handle.request
        total = goal.time.sec + goal.time.nanosec / 1e9
        feedback = Wait.Feedback()

        def cycle(elapsed: float) -> tuple[float, float] | None:
            feedback.time_left = duration_msg(total - elapsed)
            handle.publish_feedback(feedback)
            return None if elapsed >= total else (0.0, 0.0)
        return self._loop(handle, Wait.Result(), None, cycle, 0)

    def _assisted_teleop(self, handle: Any) -> Any:
        self._preempt.clear()
        self._teleop = (0.0, 0.0, 0.0)
        feedback = AssistedTeleop.Feedback()

        def cycle(elapsed: float) -> tuple[float, float] | None:
            feedback.current_teleop_duration = duration_msg(elapsed)
            handle.publish_feedback(feedback)
            if self._preempt.is_set():
                return None
            twist = self._teleop
            if not any(twist):
                return 0.0, 0.0
            times, poses = projected_poses(self._pose(), twist, self.simulation_time_step, self.projection_time)
            scale = collision_scale(times, self._blocked_each(poses[:, :2]), self.projection_time)
            return twist[0] * scale, twist[2] * scale
        return self._loop(handle, AssistedTeleop.Result(), handle.request.time_allowance, cycle, 730)


class _Abort(Exception):
    def __init__(self, offset: int, message: str) -> None:
        super().__init__(message)
        self.offset = offset


def main(args: list[str] | None = None) -> int:
    try:
        with zros.init(args=args):
            spin_nodes(BehaviorServer())
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    return 0


if __name__ == '__main__':
    sys.exit(main())
