"""nav2_waypoint_follower's waypoint_follower: `follow_waypoints` drives through poses one by one
with navigate_to_pose, pausing at each.

    zros run nav2_waypoint_follower waypoint_follower --ros-args --params-file burger.yaml

A lifecycle node. Parameters as Nav2's: `loop_rate`, `stop_on_failure` (false: a waypoint that
fails is added to the result's `missed_waypoints` and the next one is tried),
`waypoint_task_executor_plugin` with `<plugin>.waypoint_pause_duration` [ms] (wait_at_waypoint).
Feedback `current_waypoint` is the index being driven to. Cancel cancels the current navigation.
"""
from __future__ import annotations

import sys
from typing import Any

import zros
from zros.action import ActionClient
from zros.executors import ExternalShutdownException, spin_nodes
from zros.lifecycle import LifecycleNode
from zros.navigation.node_support import Nav2Params
from zros.navigation.servers import GoalCall, GoalRunner, gated_action_server

from interfaces.action_msgs.msg import GoalStatus
from interfaces.nav2_msgs.action import FollowWaypoints, NavigateToPose

_TASK_EXECUTOR_FAILED = 601


class WaypointFollower(LifecycleNode):
    def __init__(self) -> None:
        super().__init__('waypoint_follower')
        prm = Nav2Params(self)
        self.loop_rate = prm.get('loop_rate', 20.0)
        self.stop_on_failure = prm.get('stop_on_failure', True)
        plugin = prm.get('waypoint_task_executor_plugin', 'wait_at_waypoint')
        prm.get(f'{plugin}.plugin', 'nav2_waypoint_follower::WaitAtWaypoint')
        self.pause_s = prm.get(f'{plugin}.waypoint_pause_duration', 0) / 1000.0
        self.pause_enabled = prm.get(f'{plugin}.enabled', True)
        prm.report_unused()
        self.goals = GoalRunner(self)
        self.nav_client = ActionClient(self, NavigateToPose, 'navigate_to_pose')
        gated_action_server(self, FollowWaypoints, 'follow_waypoints', self._follow)

    def _follow(self, handle: Any) -> Any:
        poses = list(handle.request.poses)
        result = FollowWaypoints.Result()
        feedback = FollowWaypoints.Feedback()
        self.goals.slot.take(handle)
        self.get_logger().info(f'Received follow waypoint request with {len(poses)} waypoints.')
        # One waypoint at a time: drive to it (`call`), then pause there until `resume_ns`.
        state: dict[str, Any] = {'index': -1, 'call': None, 'resume_ns': 0}

        def next_waypoint() -> Any:
            state['index'] += 1
            if state['index'] == len(poses):
                self.get_logger().info(f'Completed all {len(poses)} waypoints requested.')
                handle.succeed()
                return result
            feedback.current_waypoint = state['index']
            handle.publish_feedback(feedback)
            state['call'] = GoalCall(self.nav_client, NavigateToPose.Goal(pose=poses[state['index']]))
            return None

        def step() -> Any:
            call, index = state['call'], state['index']
            if call is None:
                if self.get_clock().now().nanoseconds < state['resume_ns']:
                    return None
                return next_waypoint()
            if not call.poll():
                return None
            state['call'] = None
            if call.status != GoalStatus.STATUS_SUCCEEDED:
                self.get_logger().warn(f'Failed to process waypoint {index} in waypoint list and '
                                       f'stop on failure is {"enabled" if self.stop_on_failure else "disabled"}.')
                result.missed_waypoints.append(index)
                if self.stop_on_failure:
                    return self.goals.fail(handle, result, _TASK_EXECUTOR_FAILED,
                                           f'waypoint {index} failed: {getattr(call.result, "error_msg", "")}')
                return next_waypoint()
            self.get_logger().info(f'Succeeded processing waypoint {index}, processing waypoint task execution')
            if self.pause_enabled and self.pause_s > 0:
                state['resume_ns'] = self.get_clock().now().nanoseconds + int(self.pause_s * 1e9)
            return None

        def cancel_navigation() -> None:
            if state['call'] is not None:
                state['call'].cancel()
        return self.goals.loop(handle, result, self.loop_rate, step, on_interrupt=cancel_navigation)


def main(args: list[str] | None = None) -> int:
    try:
        with zros.init(args=args):
            spin_nodes(WaypointFollower())
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    return 0


if __name__ == '__main__':
    sys.exit(main())
