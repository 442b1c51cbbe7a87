"""nav2_waypoint_follower's waypoint_follower: `follow_waypoints` drives through poses one by one
with navigate_to_pose, pausing at each; `follow_gps_waypoints` (Nav2 Jazzy) does the same with
GPS poses, which it first turns into poses in `global_frame_id` (map) through robot_localization's
`/fromLL` service (navsat_transform_node offers it).

    zros run nav2_waypoint_follower waypoint_follower --ros-args --params-file burger.yaml

A lifecycle node. Parameters as Nav2's: `loop_rate`, `stop_on_failure` (false: a waypoint that
fails is added to the result's `missed_waypoints` and the next one is tried),
`waypoint_task_executor_plugin` with `<plugin>.waypoint_pause_duration` [ms] (wait_at_waypoint).
Feedback `current_waypoint` is the index being driven to. Cancel cancels the current navigation.
A GPS goal's `goal_index` is where the first round starts and `number_of_loops` how many more
rounds follow, as in Nav2; a GPS pose `/fromLL` cannot convert is skipped and listed as missed,
or, with `stop_on_failure`, fails the goal before the robot moves.
"""
from __future__ import annotations

import sys
from typing import Any, Callable

import zros
from zros.action import ActionClient
from zros.executors import ExternalShutdownException, spin_nodes
from zros.lifecycle import LifecycleNode
from zros.navigation.node_support import Nav2Params
from zros.navigation.servers import GoalCall, GoalRunner, gated_action_server, MISSION_RESULT_TIMEOUT_S

from interfaces.action_msgs.msg import GoalStatus
from interfaces.geometry_msgs.msg import PoseStamped
from interfaces.nav2_msgs.action import FollowGPSWaypoints, FollowWaypoints, NavigateToPose
from interfaces.nav2_msgs.msg import MissedWaypoint
from interfaces.robot_localization.srv import FromLL

_TASK_EXECUTOR_FAILED = 601
_UNKNOWN = 600
_FROM_LL_TIMEOUT_S = 1.0     # Nav2 waits a second for /fromLL before each conversion


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
        self.global_frame_id = prm.get('global_frame_id', 'map').lstrip('/')
        result_timeout = prm.get('action_server_result_timeout', MISSION_RESULT_TIMEOUT_S)
        prm.report_unused()
        self.goals = GoalRunner(self)
        self.nav_client = ActionClient(self, NavigateToPose, 'navigate_to_pose')
        self.from_ll = self.create_client(FromLL, '/fromLL')
        gated_action_server(self, FollowWaypoints, 'follow_waypoints', self._follow, result_timeout=result_timeout)
        gated_action_server(self, FollowGPSWaypoints, 'follow_gps_waypoints', self._follow_gps,
                            result_timeout=result_timeout)

    def _follow(self, handle: Any) -> Any:
        poses = list(handle.request.poses)
        self.goals.slot.take(handle)
        self.get_logger().info(f'Received follow waypoint request with {len(poses)} waypoints.')
        return self._drive(handle, list(enumerate(poses)), FollowWaypoints.Result(), FollowWaypoints.Feedback(),
                           missed=lambda index, pose, call: index)

    def _follow_gps(self, handle: Any) -> Any:
        goal = handle.request
        result = FollowGPSWaypoints.Result()
        self.goals.slot.take(handle)
        self.get_logger().info(f'Received follow GPS waypoint request with {len(goal.gps_poses)} waypoints.')
        if goal.gps_poses and goal.goal_index >= len(goal.gps_poses):
            return self.goals.fail(handle, result, _UNKNOWN, f'goal_index {goal.goal_index} is past the last of '
                                                             f'{len(goal.gps_poses)} waypoints')
        poses = self._to_global_frame(goal.gps_poses, result)
        if poses is None:
            return self.goals.fail(handle, result, _TASK_EXECUTOR_FAILED,
                                   f'a GPS waypoint could not be converted to {self.global_frame_id} and '
                                   'stop_on_failure is true: no waypoint was driven to')
        rounds = [(i, pose) for i, pose in poses if i >= goal.goal_index] + poses * goal.number_of_loops
        return self._drive(handle, rounds, result, FollowGPSWaypoints.Feedback(),
                           missed=lambda index, pose, call: MissedWaypoint(
                               index=index, goal=pose,
                               error_code=int(getattr(call.result, 'error_code', 0) or _TASK_EXECUTOR_FAILED)))

    def _to_global_frame(self, gps_poses: list[Any], result: Any) -> list[tuple[int, Any]] | None:
        """(index in the goal, PoseStamped in the global frame) of each GPS pose, through /fromLL;
        a pose that cannot be converted is left out (listed missed) or, with stop_on_failure, None."""
        self.get_logger().info(f'Converting GPS waypoints to {self.global_frame_id} Frame..')
        poses = []
        for index, geopose in enumerate(gps_poses):
            response = None
            if self.from_ll.wait_for_service(timeout_sec=_FROM_LL_TIMEOUT_S):
                response = self.from_ll.call(FromLL.Request(ll_point=geopose.position), timeout_sec=_FROM_LL_TIMEOUT_S)
            if response is None:
                self.get_logger().error(f'fromLL service of robot_localization could not convert waypoint {index} '
                                        f'to the {self.global_frame_id} frame (is navsat_transform_node running?)')
                if self.stop_on_failure:
                    return None
                result.missed_waypoints.append(MissedWaypoint(index=index, error_code=_TASK_EXECUTOR_FAILED))
                continue
            pose = PoseStamped()
            pose.header.frame_id = self.global_frame_id
            pose.header.stamp = self.get_clock().now().to_msg()
            pose.pose.position, pose.pose.orientation = response.map_point, geopose.orientation
            poses.append((index, pose))
        self.get_logger().info(f'Converted all {len(poses)} GPS waypoint to {self.global_frame_id} frame')
        return poses

    def _drive(self, handle: Any, poses: list[tuple[int, Any]], result: Any, feedback: Any,
               missed: Callable[[int, Any, GoalCall], Any]) -> Any:
        """Drive to `poses` ((waypoint number, PoseStamped) pairs) one at a time with
        navigate_to_pose, pausing at each; feedback names the waypoint number, and a waypoint that
        fails goes into the result's missed_waypoints as `missed(number, pose, call)` says."""
        # One waypoint at a time: drive to it (`call`), then pause there until `resume_ns`.
        state: dict[str, Any] = {'index': -1, 'call': None, 'resume_ns': 0}

        def next_waypoint() -> Any:
            state['index'] += 1
            if state['index'] == len(poses):
                self.get_logger().info(f'Completed all {len(poses)} waypoints requested.')
                handle.succeed()
                return result
            number, pose = poses[state['index']]
            feedback.current_waypoint = number
            handle.publish_feedback(feedback)
            state['call'] = GoalCall(self.nav_client, NavigateToPose.Goal(pose=pose))
            return None

        def step() -> Any:
            call = state['call']
            if call is None:
                if self.get_clock().now().nanoseconds < state['resume_ns']:
                    return None
                return next_waypoint()
            if not call.poll():
                return None
            state['call'] = None
            index, pose = poses[state['index']]
            if call.status != GoalStatus.STATUS_SUCCEEDED:
                self.get_logger().warn(f'Failed to process waypoint {index} in waypoint list and '
                                       f'stop on failure is {"enabled" if self.stop_on_failure else "disabled"}.')
                result.missed_waypoints.append(missed(index, pose, call))
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
