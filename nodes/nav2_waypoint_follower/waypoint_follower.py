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
from zros.exceptions import ROSInterruptException
from zros.lifecycle import LifecycleNode
from zros.navigation.node_support import Nav2Params, spin_nodes
from zros.navigation.servers import GoalCall, GoalSlot, gated_action_server

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
        self.slot = GoalSlot()
        self.nav_client = ActionClient(self, NavigateToPose, 'navigate_to_pose')
        gated_action_server(self, FollowWaypoints, 'follow_waypoints', self._follow)

    def _follow(self, handle: Any) -> Any:
        poses = list(handle.request.poses)
        result = FollowWaypoints.Result()
        feedback = FollowWaypoints.Feedback()
        missed: list[int] = []
        self.slot.take(handle)
        self.get_logger().info(f'Received follow waypoint request with {len(poses)} waypoints.')
        rate = self.create_rate(self.loop_rate)
        try:
            for index, pose in enumerate(poses):
                feedback.current_waypoint = index
                handle.publish_feedback(feedback)
                call = GoalCall(self.nav_client, NavigateToPose.Goal(pose=pose))
                while not call.poll():
                    if not self.slot.is_current(handle) or handle.is_cancel_requested:
                        call.cancel()
                        result.missed_waypoints = missed
                        if handle.is_cancel_requested:
                            handle.canceled()
                        else:
                            handle.abort()
                        return result
                    rate.sleep()
                if call.status != GoalStatus.STATUS_SUCCEEDED:
                    self.get_logger().warn(f'Failed to process waypoint {index} in waypoint list and '
                                           f'stop on failure is {"enabled" if self.stop_on_failure else "disabled"}.')
                    missed.append(index)
                    if self.stop_on_failure:
                        result.missed_waypoints = missed
                        result.error_code = _TASK_EXECUTOR_FAILED
                        result.error_msg = f'waypoint {index} failed: {getattr(call.result, "error_msg", "")}'
                        handle.abort()
                        return result
                    continue
                self.get_logger().info(f'Succeeded processing waypoint {index}, processing waypoint task execution')
                if self.pause_enabled and self.pause_s > 0:
                    end = self.get_clock().now().nanoseconds + int(self.pause_s * 1e9)
                    while self.get_clock().now().nanoseconds < end:
                        rate.sleep()
        except ROSInterruptException:
            handle.abort()
            return result
        finally:
            rate.destroy()
            self.slot.release(handle)
        result.missed_waypoints = missed
        self.get_logger().info(f'Completed all {len(poses)} waypoints requested.')
        handle.succeed()
        return result


def main(args: list[str] | None = None) -> int:
    with zros.init(args=args):
        spin_nodes(WaypointFollower())
    return 0


if __name__ == '__main__':
    sys.exit(main())
