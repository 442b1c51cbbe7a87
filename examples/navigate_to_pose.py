"""Send the robot to a pose on the map with Nav2's BasicNavigator, and report how it went.

    python examples/navigate_to_pose.py 1.0 0.5                       # x y [m], facing +x
    python examples/navigate_to_pose.py 1.0 0.5 --yaw 1.57 --initial-pose -2.0 -0.5 0.0

Needs the simulator and Nav2 up, as in docs/navigation.md:
`zros launch turtlebot3_gazebo turtlebot3_world.launch.py` and
`zros launch turtlebot3_navigation2 navigation2.launch.py use_sim_time:=True`.
"""
from __future__ import annotations

import argparse
import sys

import zros
from zros.nav2_simple_commander.robot_navigator import BasicNavigator, TaskResult
from zros.tf_transformations import quaternion_from_euler

from interfaces.geometry_msgs.msg import PoseStamped

from common import parse_args, run


def map_pose(navigator: BasicNavigator, x: float, y: float, yaw: float) -> PoseStamped:
    """A PoseStamped in the map frame at (x, y) [m], heading yaw [rad] (counter-clockwise from +x)."""
    pose = PoseStamped()
    pose.header.frame_id = 'map'
    pose.header.stamp = navigator.get_clock().now().to_msg()
    pose.pose.position.x, pose.pose.position.y = x, y
    q = quaternion_from_euler(0.0, 0.0, yaw)   # x, y, z, w
    pose.pose.orientation.x, pose.pose.orientation.y = float(q[0]), float(q[1])
    pose.pose.orientation.z, pose.pose.orientation.w = float(q[2]), float(q[3])
    return pose


def main(goal: tuple[float, float, float], initial_pose: tuple[float, float, float] | None, timeout: float,
         ros_args: list[str]) -> int:
    with zros.init(args=ros_args), BasicNavigator() as navigator:
        if initial_pose is not None:
            navigator.setInitialPose(map_pose(navigator, *initial_pose))   # RViz's 2D Pose Estimate
        if not navigator.waitUntilNav2Active(timeout=timeout):
            print(f'navigate_to_pose: Nav2 not active after {timeout:g} s', file=sys.stderr)
            return 1
        navigator.goToPose(map_pose(navigator, *goal))
        turns = 0
        while not navigator.isTaskComplete():   # spins the navigator 0.1 s at a time
            turns += 1
            feedback = navigator.getFeedback()
            if feedback is not None and turns % 10 == 0:   # about once a second
                navigator.info(f'distance remaining: {feedback.distance_remaining:.2f} m')
        result = navigator.getResult()
        navigator.info(f'result: {result.name}')
    return 0 if result == TaskResult.SUCCEEDED else 1


if __name__ == '__main__':
    parser = argparse.ArgumentParser(prog='navigate_to_pose', description='Drive to a pose with BasicNavigator.')
    parser.add_argument('x', type=float, help='goal x in the map frame [m]')
    parser.add_argument('y', type=float, help='goal y in the map frame [m]')
    parser.add_argument('--yaw', type=float, default=0.0, help='goal heading [rad] (default: 0)')
    parser.add_argument('--initial-pose', type=float, nargs=3, metavar=('X', 'Y', 'YAW'),
                        help='tell AMCL where the robot starts (map frame [m], [rad])')
    parser.add_argument('--timeout', type=float, default=60.0, help='wait for Nav2 to be active [s]')
    args = parse_args(parser)
    initial = tuple(args.initial_pose) if args.initial_pose else None
    run(main, (args.x, args.y, args.yaw), initial, args.timeout)
