"""nav2_bt_navigator's bt_navigator: `navigate_to_pose`, `navigate_through_poses` and `goal_pose`.

    zros run nav2_bt_navigator bt_navigator --ros-args --params-file burger.yaml

Nav2 runs a behaviour tree (navigate_to_pose_w_replanning_and_recovery.xml); zros runs the same
control flow written as one plain function, `navigate()` below, which reads top to bottom like
the tree: plan, follow while replanning at `replan_frequency`, and when that fails run the next
recovery of the round (clear costmaps, spin, wait, back up) and try again, up to
`number_of_retries` times. To change the flow, change that function (docs/navigation.md).

A lifecycle node. Feedback has Nav2's fields (current_pose from TF, navigation_time,
estimated_time_remaining = distance / speed, number_of_recoveries, distance_remaining along the
path, number_of_poses_remaining). A new goal on either action preempts the running one (which
ends ABORTED); a cancel stops the robot (the follow goal is cancelled). A goal that fails ends
ABORTED with the failing server's error code and message in the result.
"""
from __future__ import annotations

import math
import sys
from dataclasses import dataclass
from typing import Any

import numpy as np

import zros
from zros.action import ActionClient
from zros.exceptions import ROSInterruptException
from zros.executors import ExternalShutdownException, spin_nodes
from zros.lifecycle import LifecycleNode, State, TransitionCallbackReturn
from zros.navigation.node_support import Nav2Params, duration_msg, lookup_pose, quaternion_of
from zros.navigation.servers import GoalCall, GoalSlot, gated_action_server, MISSION_RESULT_TIMEOUT_S
from zros.tf2_ros import Buffer, TransformListener

from interfaces.action_msgs.msg import GoalStatus
from interfaces.geometry_msgs.msg import PoseStamped
from interfaces.nav2_msgs.action import (BackUp, ComputePathThroughPoses, ComputePathToPose, FollowPath,
                                         NavigateThroughPoses, NavigateToPose, Spin, Wait)
from interfaces.nav2_msgs.srv import ClearEntireCostmap
from interfaces.nav_msgs.msg import Odometry

# Planner errors no recovery can fix: fail at once instead of spinning and backing up for nothing.
_HOPELESS = {203, 204, 206, 303, 304, 306, 309}
_PASSED_GOAL_RADIUS = 0.5     # [m] NavigateThroughPoses drops a pose once the robot is this close


@dataclass
class Outcome:
    """How a step ended: SUCCEEDED, FAILED (with the error), CANCELED or PREEMPTED."""

    state: str
    code: int = 0
    message: str = ''


# ---------------------------------------------------------------------------------------------
# The control flow (the behaviour tree's role). `nav` is the Navigation object of one goal.
# ---------------------------------------------------------------------------------------------
def navigate(nav: 'Navigation') -> Outcome:
    """navigate_to_pose_w_replanning_and_recovery, as a function."""
    recoveries = [nav.clear_costmaps, lambda: nav.spin(1.57), lambda: nav.wait(5.0), lambda: nav.backup(0.30, 0.05)]
    while True:
        outcome = nav.follow_with_replanning()
        if outcome.state != 'FAILED' or outcome.code in _HOPELESS:
            return outcome
        if nav.recoveries >= nav.number_of_retries:
            return outcome
        nav.get_logger().info(f'Navigation failed ({outcome.message}); recovery {nav.recoveries + 1} '
                              f'of {nav.number_of_retries}')
        recovery = recoveries[nav.recoveries % len(recoveries)]
        nav.recoveries += 1
        interrupted = recovery()
        if interrupted is not None:
            return interrupted


class Navigation:
    """One goal being navigated: the steps `navigate()` combines, and the feedback they publish."""

    def __init__(self, server: 'BtNavigator', handle: Any, poses: list) -> None:
        self.server = server
        self.handle = handle
        self.poses = poses
        self.through = isinstance(handle.request, NavigateThroughPoses.Goal)
        self.recoveries = 0
        self.number_of_retries = server.number_of_retries
        self.started = server.get_clock().now()
        self.path = np.zeros((0, 2))
        self.get_logger = server.get_logger

    # -- interruption ------------------------------------------------------------------------
    def interrupted(self) -> Outcome | None:
        if not self.server.slot.is_current(self.handle):
            return Outcome('PREEMPTED')
        if self.handle.is_cancel_requested:
            return Outcome('CANCELED')
        if self.server.current_state.label != 'active':
            return Outcome('FAILED', 0, 'bt_navigator was deactivated')
        return None

    def _run(self, client: Any, goal: Any, feedback: bool = True) -> tuple[Outcome, Any]:
        """Send a goal and wait for it, publishing feedback and watching for cancel/preemption."""
        call = GoalCall(client, goal)
        rate = self.server.create_rate(self.server.loop_frequency)
        try:
            while not call.poll():
                stop = self.interrupted()
                if stop is not None:
                    call.cancel()
                    return stop, None
                if feedback:
                    self.publish_feedback()
                rate.sleep()
        finally:
            rate.destroy()
        if call.status == GoalStatus.STATUS_SUCCEEDED:
            return Outcome('SUCCEEDED'), call.result
        code = getattr(call.result, 'error_code', 0) if call.result is not None else 0
        message = getattr(call.result, 'error_msg', '') if call.result is not None else ''
        return Outcome('FAILED', code, message or f'{type(goal).__name__} ended with status {call.status}'), call.result

    # -- steps -------------------------------------------------------------------------------
    def compute_path(self) -> tuple[Outcome, Any]:
        self.drop_passed_poses()
        if self.through:
            goal = ComputePathThroughPoses.Goal(goals=list(self.poses), planner_id='')
            client = self.server.plan_through_client
        else:
            goal = ComputePathToPose.Goal(goal=self.poses[-1], planner_id='')
            client = self.server.plan_client
        outcome, result = self._run(client, goal, feedback=False)
        if outcome.state == 'SUCCEEDED':
            self.path = np.array([[p.pose.position.x, p.pose.position.y] for p in result.path.poses]).reshape(-1, 2)
            return outcome, result.path
        return outcome, None

    def follow_with_replanning(self) -> Outcome:
        """Plan (clearing the global costmap and retrying once on failure), then follow the path,
        sending a new plan to the controller every 1/replan_frequency seconds."""
        outcome, path = self.compute_path()
        if outcome.state == 'FAILED' and outcome.code not in _HOPELESS:
            self.server.clear('global')
            outcome, path = self.compute_path()
        if path is None:
            return outcome
        follow = GoalCall(self.server.follow_client, FollowPath.Goal(path=path))
        rate = self.server.create_rate(self.server.loop_frequency)
        period_ns = int(1e9 / self.server.replan_frequency) if self.server.replan_frequency > 0 else None
        last_plan = self.server.get_clock().now().nanoseconds
        try:
            while not follow.poll():
                stop = self.interrupted()
                if stop is not None:
                    follow.cancel()
                    return stop
                self.publish_feedback()
                now = self.server.get_clock().now().nanoseconds
                if period_ns is not None and now - last_plan >= period_ns:
                    last_plan = now
                    outcome, path = self.compute_path()
                    if outcome.state in ('CANCELED', 'PREEMPTED'):
                        follow.cancel()
                        return outcome
                    if follow.poll():
                        break           # it ended while the path was computed: that is the outcome (the tree's FollowPath)
                    if path is not None and follow.running:   # an ended goal's result is on its way
                        follow = GoalCall(self.server.follow_client, FollowPath.Goal(path=path))
                rate.sleep()
        finally:
            rate.destroy()
        if follow.status == GoalStatus.STATUS_SUCCEEDED:
            return Outcome('SUCCEEDED')
        if follow.status == GoalStatus.STATUS_CANCELED:
            return self.interrupted() or Outcome('CANCELED')
        result = follow.result
        return Outcome('FAILED', getattr(result, 'error_code', 0), getattr(result, 'error_msg', '') or 'follow_path failed')

    def clear_costmaps(self) -> Outcome | None:
        self.server.clear('global')
        self.server.clear('local')
        return None

    def spin(self, yaw: float) -> Outcome | None:
        return self._behavior(self.server.spin_client, Spin.Goal(target_yaw=yaw, time_allowance=duration_msg(10.0)))

    def wait(self, seconds: float) -> Outcome | None:
        return self._behavior(self.server.wait_client, Wait.Goal(time=duration_msg(seconds)))

    def backup(self, distance: float, speed: float) -> Outcome | None:
        goal = BackUp.Goal(speed=speed, time_allowance=duration_msg(10.0))
        goal.target.x = distance
        return self._behavior(self.server.backup_client, goal)

    def _behavior(self, client: Any, goal: Any) -> Outcome | None:
        outcome, _ = self._run(client, goal)
        return outcome if outcome.state in ('CANCELED', 'PREEMPTED') else None

    # -- feedback ----------------------------------------------------------------------------
    def drop_passed_poses(self) -> None:
        if not self.through or len(self.poses) <= 1:
            return
        try:
            x, y, _ = self.server.robot_pose()
        except Exception:  # noqa: BLE001 - no TF yet
            return
        while len(self.poses) > 1 and math.hypot(self.poses[0].pose.position.x - x,
                                                 self.poses[0].pose.position.y - y) < _PASSED_GOAL_RADIUS:
            self.poses.pop(0)

    def publish_feedback(self) -> None:
        feedback = (NavigateThroughPoses if self.through else NavigateToPose).Feedback()
        try:
            x, y, yaw = self.server.robot_pose()
        except Exception:  # noqa: BLE001 - no TF yet: no feedback this time
            return
        now = self.server.get_clock().now()
        current = feedback.current_pose
        current.header.frame_id = self.server.global_frame
        current.header.stamp = now.to_msg()
        current.pose.position.x, current.pose.position.y = x, y
        quaternion_of(yaw, current.pose.orientation)
        remaining = 0.0
        if len(self.path):
            closest = int(np.argmin(np.hypot(self.path[:, 0] - x, self.path[:, 1] - y)))
            rest = self.path[closest:]
            remaining = float(np.linalg.norm(np.diff(rest, axis=0), axis=1).sum()) if len(rest) > 1 else 0.0
        feedback.distance_remaining = remaining
        speed = abs(self.server.speed)
        eta = remaining / speed if speed > 0.01 and remaining > 0.1 else 0.0
        feedback.estimated_time_remaining = duration_msg(eta)
        feedback.navigation_time = duration_msg((now - self.started).nanoseconds / 1e9)
        feedback.number_of_recoveries = self.recoveries
        if self.through:
            feedback.number_of_poses_remaining = len(self.poses)
        self.handle.publish_feedback(feedback)


class BtNavigator(LifecycleNode):
    def __init__(self) -> None:
        super().__init__('bt_navigator')
        self.tf_buffer = Buffer(node=self)
        self.tf_listener = TransformListener(self.tf_buffer, self)
        prm = Nav2Params(self)
        self.global_frame = prm.get('global_frame', 'map')
        self.robot_base_frame = prm.get('robot_base_frame', 'base_link')
        odom_topic = prm.get('odom_topic', 'odom')
        self.loop_frequency = 1000.0 / max(prm.get('bt_loop_duration', 10), 1) / 5.0   # feedback at 20 Hz
        self.replan_frequency = prm.get('replan_frequency', 1.0)
        self.number_of_retries = prm.get('number_of_retries', 6)
        result_timeout = prm.get('action_server_result_timeout', MISSION_RESULT_TIMEOUT_S)
        prm.report_unused()
        self.speed = 0.0
        self.slot = GoalSlot()
        self.plan_client = ActionClient(self, ComputePathToPose, 'compute_path_to_pose')
        self.plan_through_client = ActionClient(self, ComputePathThroughPoses, 'compute_path_through_poses')
        self.follow_client = ActionClient(self, FollowPath, 'follow_path')
        self.spin_client = ActionClient(self, Spin, 'spin')
        self.backup_client = ActionClient(self, BackUp, 'backup')
        self.wait_client = ActionClient(self, Wait, 'wait')
        self.self_client = ActionClient(self, NavigateToPose, 'navigate_to_pose')
        self.clear_clients = {
            'global': self.create_client(ClearEntireCostmap, 'global_costmap/clear_entirely_global_costmap'),
            'local': self.create_client(ClearEntireCostmap, 'local_costmap/clear_entirely_local_costmap')}
        self.create_subscription(Odometry, odom_topic, self._on_odom, 10)
        self.create_subscription(PoseStamped, 'goal_pose', self._on_goal_pose, 10)
        gated_action_server(self, NavigateToPose, 'navigate_to_pose', self._execute, result_timeout=result_timeout)
        gated_action_server(self, NavigateThroughPoses, 'navigate_through_poses', self._execute,
                            result_timeout=result_timeout)

    def on_configure(self, state: State) -> TransitionCallbackReturn:
        self.get_logger().info('Configuring: navigate_to_pose and navigate_through_poses (plan, follow, replan, recover)')
        return TransitionCallbackReturn.SUCCESS

    def _on_odom(self, msg: Any) -> None:
        self.speed = msg.twist.twist.linear.x

    def _on_goal_pose(self, msg: Any) -> None:
        """RViz's Nav2 Goal: forwarded to our own navigate_to_pose, as Nav2 does."""
        if self.current_state.label != 'active':
            self.get_logger().warn('goal_pose received while bt_navigator is not active: ignored')
            return
        self.get_logger().info(f'Received goal_pose ({msg.pose.position.x:.2f}, {msg.pose.position.y:.2f})')
        self.self_client.send_goal_async(NavigateToPose.Goal(pose=msg))

    def robot_pose(self) -> tuple[float, float, float]:
        return lookup_pose(self.tf_buffer, self.global_frame, self.robot_base_frame)

    def clear(self, which: str) -> None:
        client = self.clear_clients[which]
        if client.service_is_ready():
            client.call_async(ClearEntireCostmap.Request())

    def _execute(self, handle: Any) -> Any:
        request = handle.request
        through = isinstance(request, NavigateThroughPoses.Goal)
        result = (NavigateThroughPoses if through else NavigateToPose).Result()
        poses = list(request.poses) if through else [request.pose]
        for pose in poses:
            if not pose.header.frame_id:
                pose.header.frame_id = self.global_frame
        self.slot.take(handle)
        target = poses[-1].pose.position if poses else None
        if target is None:
            result.error_msg = 'No poses given'
            handle.abort()
            return result
        self.get_logger().info(f'Begin navigating from current location to ({target.x:.2f}, {target.y:.2f})')
        nav = Navigation(self, handle, poses)
        try:
            outcome = navigate(nav)
        except ROSInterruptException:
            outcome = Outcome('FAILED', 0, 'shutting down')
        finally:
            self.slot.release(handle)
        if outcome.state == 'SUCCEEDED':
            self.get_logger().info('Goal succeeded')
            handle.succeed()
        elif outcome.state == 'CANCELED':
            self.get_logger().info('Goal canceled')
            handle.canceled()
        else:
            result.error_code = outcome.code
            result.error_msg = outcome.message or 'preempted by a new goal'
            self.get_logger().warn(f'Goal failed: {result.error_msg} (error code {outcome.code})'
                                   if outcome.state == 'FAILED' else 'Goal preempted by a new goal')
            handle.abort()
        return result


def main(args: list[str] | None = None) -> int:
    try:
        with zros.init(args=args):
            spin_nodes(BtNavigator(), num_threads=8)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    return 0


if __name__ == '__main__':
    sys.exit(main())
