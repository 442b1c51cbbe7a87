"""`zros launch turtlebot3_gazebo turtlebot3_world...` end to end: the world, the robot where the
arguments put it, robot_state_publisher on the shipped URDF, a whole TF tree, and Ctrl-C."""
from __future__ import annotations

import signal
import sys
import threading
from typing import Any

import pytest

from conftest import wait_until


@pytest.mark.parametrize('launch_file', ['turtlebot3_world.launch.yaml'])
def test_turtlebot3_world_launch_gives_the_robot_and_its_tf_tree(spawn: Any, context: Any, launch_file: str) -> None:
    from zros.executors import MultiThreadedExecutor
    from zros.node import Node
    from zros.tf2_ros import Buffer, TransformListener
    from zros.time import Time
    from interfaces.gazebo_msgs.srv import GetEntityState
    launch = spawn(sys.executable, '-m', 'zros', 'launch', 'turtlebot3_gazebo', launch_file,
                   'x_pose:=0.5', 'y_pose:=2.0', 'real_time_factor:=5.0', name='launch')
    node = Node('launch_test', context=context)
    buffer = Buffer()
    TransformListener(buffer, node)
    executor = MultiThreadedExecutor(context=context)
    executor.add_node(node)
    threading.Thread(target=executor.spin, daemon=True).start()
    try:
        client = node.create_client(GetEntityState, '/get_entity_state')
        assert client.wait_for_service(timeout_sec=30), launch.output()
        state = client.call(GetEntityState.Request(name='burger'), timeout_sec=10)
        assert state.success and (state.state.pose.position.x, state.state.pose.position.y) == (0.5, 2.0)
        # odom -> base_footprint from the simulator, base_footprint -> ... -> base_scan from
        # robot_state_publisher: the chain students look up.
        wait_until(lambda: buffer.can_transform('odom', 'base_scan', Time()), 20,
                   message=lambda: f'odom -> base_scan; frames: {buffer.all_frames_as_string()}\n{launch.output()}')
        t = buffer.lookup_transform('odom', 'base_scan', Time()).transform.translation
        assert (t.x, t.y, t.z) == pytest.approx((-0.032, 0.0, 0.182), abs=1e-6)
        wait_until(lambda: buffer.can_transform('base_link', 'wheel_left_link', Time()), 20,
                   message='the wheels from joint_states')
        assert 'robot_state_publisher' in {n for n, _ in node.get_node_names_and_namespaces()}
    finally:
        executor.shutdown(timeout_sec=2)
    launch.signal(signal.SIGINT)
    assert launch.wait(10) == 0, launch.output()
    assert 'process has finished cleanly' in launch.output()
