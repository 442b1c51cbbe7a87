"""navigation_from_text: drive through goals read from a text file, one `x y w` line each, with a
plain ActionClient on navigate_to_pose, as the course's own node of that name does.

    zros run navigation_from_text navigation_from_text --ros-args -p goals_file:=goals.txt

It waits until the nodes in `wait_for` (default amcl and bt_navigator) report `active` on their
`<node>/get_state` service, then sends each goal, prints the estimated time of arrival from the
feedback, cancels a goal that takes longer than `max_navigation_time` [s], and reports each
outcome by its GoalStatus. `w` is the orientation quaternion's w, as in the course's file (the
navigator normalises the quaternion: a lone w faces +x).
"""
from __future__ import annotations

import os
import sys
from typing import Any

import zros
from zros.action import ActionClient
from zros.ament_index_python.packages import get_package_share_directory
from zros.node import Node
from zros.tf2_ros import Duration

from interfaces.action_msgs.msg import GoalStatus
from interfaces.geometry_msgs.msg import PoseStamped
from interfaces.lifecycle_msgs.srv import GetState
from interfaces.nav2_msgs.action import NavigateToPose


class NavigatorFromTextfile(Node):
    def __init__(self) -> None:
        super().__init__('navigation_from_text')
        default_file = os.path.join(get_package_share_directory('navigation_from_text'), 'goals.txt')
        self.goals_file = self.declare_parameter('goals_file', default_file).value
        self.wait_for = self.declare_parameter('wait_for', ['amcl', 'bt_navigator']).value
        self.max_time = Duration(seconds=self.declare_parameter('max_navigation_time', 600.0).value)
        self.client = ActionClient(self, NavigateToPose, 'navigate_to_pose')
        self.goal_handle: Any = None
        self.result_future: Any = None
        self.feedback: Any = None
        self.status: int | None = None

    def wait_until_active(self, node_name: str) -> None:
        """Poll `<node>/get_state` until its label is 'active'."""
        client = self.create_client(GetState, f'{node_name}/get_state')
        while not client.wait_for_service(timeout_sec=1.0):
            self.get_logger().info(f'{node_name}/get_state service not available, waiting...')
        state = 'unknown'
        while state != 'active':
            future = client.call_async(GetState.Request())
            zros.spin_until_future_complete(self, future, timeout_sec=5.0)
            if future.result() is not None:
                state = future.result().current_state.label
                self.get_logger().debug(f'{node_name} is {state}')
            if state != 'active':
                zros.spin_once(self, timeout_sec=1.0)
        self.destroy_client(client)

    def go_to(self, pose: PoseStamped) -> bool:
        while not self.client.wait_for_server(timeout_sec=1.0):
            self.get_logger().info("'navigate_to_pose' action server not available, waiting...")
        self.get_logger().info(f'Navigating to goal: {pose.pose.position.x} {pose.pose.position.y}...')
        send = self.client.send_goal_async(NavigateToPose.Goal(pose=pose), feedback_callback=self._on_feedback)
        zros.spin_until_future_complete(self, send)
        self.goal_handle = send.result()
        if self.goal_handle is None or not self.goal_handle.accepted:
            self.get_logger().error('Goal was rejected!')
            return False
        self.result_future = self.goal_handle.get_result_async()
        self.feedback = None
        return True

    def _on_feedback(self, msg: Any) -> None:
        self.feedback = msg.feedback

    def is_complete(self) -> bool:
        zros.spin_until_future_complete(self, self.result_future, timeout_sec=0.1)
        response = self.result_future.result()
        if response is None:
            return False
        self.status = response.status
        return True

    def follow(self) -> int | None:
        """Wait for the current goal, printing the ETA every few feedbacks; cancel if too slow."""
        ticks = 0
        while not self.is_complete():
            ticks += 1
            if self.feedback is not None and ticks % 5 == 0:
                eta = Duration.from_msg(self.feedback.estimated_time_remaining).nanoseconds / 1e9
                print(f'Estimated time of arrival: {eta:.0f} seconds.', flush=True)
            if self.feedback is not None and Duration.from_msg(self.feedback.navigation_time) > self.max_time:
                self.get_logger().warn('Navigation is taking too long: canceling the goal')
                zros.spin_until_future_complete(self, self.goal_handle.cancel_goal_async())
        outcome = {GoalStatus.STATUS_SUCCEEDED: 'Goal succeeded!', GoalStatus.STATUS_CANCELED: 'Goal was canceled!',
                   GoalStatus.STATUS_ABORTED: 'Goal failed!'}.get(self.status, 'Goal has an invalid return status!')
        self.get_logger().info(outcome)
        return self.status


def read_goals(path: str, stamp: Any) -> list[PoseStamped]:
    """One PoseStamped in `map` per `x y w` line; blank lines and # comments are skipped."""
    goals = []
    with open(path) as file:
        for number, line in enumerate(file, 1):
            words = line.split('#', 1)[0].split()
            if not words:
                continue
            if len(words) != 3:
                raise ValueError(f'{path}:{number}: expected "x y w", got {line.strip()!r}')
            x, y, w = (float(v) for v in words)
            pose = PoseStamped()
            pose.header.frame_id = 'map'
            pose.header.stamp = stamp
            pose.pose.position.x, pose.pose.position.y = x, y
            pose.pose.orientation.w = w
            goals.append(pose)
    return goals


def main(args: list[str] | None = None) -> int:
    with zros.init(args=args):
        navigator = NavigatorFromTextfile()
        try:
            goals = read_goals(navigator.goals_file, navigator.get_clock().now().to_msg())
        except (OSError, ValueError) as exc:
            navigator.get_logger().error(f'Cannot read the goals: {exc}')
            return 1
        for name in navigator.wait_for:
            if name:
                navigator.wait_until_active(name)
        for goal in goals:
            if navigator.go_to(goal):
                navigator.follow()
        navigator.get_logger().info(f'All the {len(goals)} goals processed')
    return 0


if __name__ == '__main__':
    sys.exit(main())
