"""The course's navigation day end to end: `turtlebot3_world.launch.yaml`, then TurtleBot3's
`navigation2.launch.py` (map_server with the shipped map, AMCL, the navigation servers, their
lifecycle managers), then a BasicNavigator mission script as seed 003 writes it: set the initial
pose, wait for Nav2, go to a pose, poll until done; then /reset_simulation, a new initial pose and
the same goal again. The simulator's ground truth checks the end."""
from __future__ import annotations

import math
import sys
from typing import Any

from conftest import spin_until

MISSION = '''
import sys
import zros
from zros.nav2_simple_commander.robot_navigator import BasicNavigator, TaskResult
from interfaces.geometry_msgs.msg import PoseStamped

zros.init()
navigator = BasicNavigator()
initial_pose = PoseStamped()
initial_pose.header.frame_id = 'map'
initial_pose.header.stamp = navigator.get_clock().now().to_msg()
initial_pose.pose.position.x = -2.0
initial_pose.pose.position.y = -0.5
initial_pose.pose.orientation.w = 1.0
navigator.setInitialPose(initial_pose)
navigator.waitUntilNav2Active()
goal_pose = PoseStamped()
goal_pose.header.frame_id = 'map'
goal_pose.header.stamp = navigator.get_clock().now().to_msg()
goal_pose.pose.position.x = 0.5
goal_pose.pose.position.y = 0.5
goal_pose.pose.orientation.w = 1.0
navigator.goToPose(goal_pose)
i = 0
while not navigator.isTaskComplete():
    i += 1
    feedback = navigator.getFeedback()
    if feedback and i % 20 == 0:
        print('Distance remaining: %.2f' % feedback.distance_remaining, flush=True)
result = navigator.getResult()
print('result:', result.name, flush=True)
# Gazebo's reset: time back to 0, the robot back at its spawn pose; TF listeners keep their static
# frames, AMCL takes a new initial pose, and the next goal succeeds (issue 33).
import time
from interfaces.std_srvs.srv import Empty
reset = navigator.create_client(Empty, '/reset_simulation')
reset.wait_for_service(timeout_sec=10)
zros.spin_until_future_complete(navigator, reset.call_async(Empty.Request()), timeout_sec=10)
time.sleep(2.0)
initial_pose.header.stamp = navigator.get_clock().now().to_msg()
navigator.setInitialPose(initial_pose)
time.sleep(3.0)
goal_pose.header.stamp = navigator.get_clock().now().to_msg()
navigator.goToPose(goal_pose)
while not navigator.isTaskComplete():
    pass
again = navigator.getResult()
print('after reset:', again.name, flush=True)
sys.exit(0 if result == again == TaskResult.SUCCEEDED else 1)
'''


def test_navigation2_launch_with_map_server_amcl_and_basic_navigator(spawn: Any, context: Any) -> None:
    from zros.executors import SingleThreadedExecutor
    from zros.node import Node
    from interfaces.nav_msgs.msg import Odometry
    spawn.command(sys.executable, '-m', 'zros', 'launch', 'turtlebot3_gazebo', 'turtlebot3_world.launch.yaml',
                  'real_time_factor:=3.0', name='world')
    nav = spawn.command(sys.executable, '-m', 'zros', 'launch', 'turtlebot3_navigation2', 'navigation2.launch.py',
                        'use_sim_time:=True', 'rviz:=false', name='navigation2')
    mission = spawn.script(MISSION, name='mission')
    code = mission.wait(240)
    out = mission.output()
    assert code == 0, f'{out}\n--- navigation2.launch.py\n{nav.output()[-4000:]}'
    assert 'Nav2 is ready for use!' in out and 'result: SUCCEEDED' in out and 'after reset: SUCCEEDED' in out
    node = Node('truth_reader', context=context)
    truth: list = []
    node.create_subscription(Odometry, '/sim/ground_truth', lambda m: truth.append(m.pose.pose.position), 10)
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(node)
    spin_until(executor, lambda: truth, 10, message='ground truth')
    assert math.hypot(truth[-1].x - 0.5, truth[-1].y - 0.5) < 0.35, truth[-1]
