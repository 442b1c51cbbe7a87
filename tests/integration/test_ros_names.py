"""The names students type: ROS 2's demo package names, turtlesim_msgs, both Fibonacci action
types on the demo server, and the interface packages shipped verbatim."""
from __future__ import annotations

import threading
import time

import pytest

from zros.action import ActionClient, ActionServer, CancelResponse
from zros.action.server import GoalStatus
from zros.callback_groups import ReentrantCallbackGroup
from zros.executors import MultiThreadedExecutor
from zros.node import Node


@pytest.mark.parametrize('talker_pkg,listener_pkg', [('demo_nodes_cpp', 'demo_nodes_py')])
def test_demo_package_names_run_the_demo_nodes(spawn, zros_cli, talker_pkg, listener_pkg):
    listener = spawn.node(listener_pkg, 'listener')
    spawn.node(talker_pkg, 'talker')
    listener.wait_for_output('I heard: [Hello World: ', timeout=20)
    for pkg in (talker_pkg, listener_pkg):
        usage = zros_cli('run', pkg)
        assert 'talker' in usage.stderr and 'listener' in usage.stderr and 'add_two_ints_server' in usage.stderr


def test_turtlesim_msgs_is_turtlesim_under_its_new_name(zros_cli):
    from interfaces.turtlesim.msg import Pose
    from interfaces.turtlesim_msgs.msg import Pose as NewPose
    from interfaces.turtlesim_msgs.srv import Spawn
    assert NewPose is Pose, 'one type on the wire, whichever name the code imports'
    assert Spawn._TYPE == 'turtlesim/srv/Spawn'
    shown = zros_cli('interface', 'show', 'turtlesim_msgs/srv/Spawn')
    assert shown.returncode == 0 and 'float32 theta' in shown.stdout
    listed = zros_cli('interface', 'package', 'turtlesim_msgs')
    assert 'turtlesim_msgs/action/RotateAbsolute' in listed.stdout.split()


def test_shipped_packages_have_upstream_fields():
    from interfaces.tf2_msgs.action import LookupTransform
    from interfaces.trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint, MultiDOFJointTrajectory
    goal = LookupTransform.Goal(target_frame='map', source_frame='base_link', advanced=True, fixed_frame='odom')
    assert goal.source_time.sec == 0 and goal.timeout.nanosec == 0
    assert set(LookupTransform.Result.get_fields_and_field_types()) == {'transform', 'error'}
    point = JointTrajectoryPoint(positions=[0.5, 1.0], effort=[2.0])
    traj = JointTrajectory(joint_names=['a', 'b'], points=[point])
    assert list(traj.points[0].positions) == [0.5, 1.0]
    assert traj.points[0].time_from_start.sec == 0
    assert 'MultiDOFJointTrajectoryPoint' in MultiDOFJointTrajectory.get_fields_and_field_types()['points']


def test_demo_fibonacci_server_answers_both_action_types(spawn, context):
    from interfaces.action_tutorials_interfaces.action import Fibonacci
    from interfaces.example_interfaces.action import Fibonacci as ExampleFibonacci
    spawn.node('demo_nodes', 'fibonacci_action_server', '--ros-args', '-p', 'step_period:=0.05')
    node = Node('fib_names_client', context=context)
    executor = MultiThreadedExecutor(context=context)
    executor.add_node(node)
    thread = threading.Thread(target=executor.spin, daemon=True)
    thread.start()
    try:
        example = ActionClient(node, ExampleFibonacci, 'fibonacci')
        tutorial = ActionClient(node, Fibonacci, 'fibonacci')
        assert example.wait_for_server(timeout_sec=15) and tutorial.wait_for_server(timeout_sec=5)
        feedback = []
        handle = example.send_goal_async(ExampleFibonacci.Goal(order=5), feedback_callback=feedback.append)
        assert handle.wait(10) and handle.result().accepted
        result = handle.result().get_result_async()
        assert result.wait(10) and result.result().status == GoalStatus.SUCCEEDED
        assert list(result.result().result.sequence) == [0, 1, 1, 2, 3, 5]
        assert list(feedback[-1].feedback.sequence) == [0, 1, 1, 2, 3, 5]
        # Cancel reaches the goal whichever type it is of (one cancel service for both).
        for client, action in ((tutorial, Fibonacci), (example, ExampleFibonacci)):
            sent = client.send_goal_async(action.Goal(order=60))
            assert sent.wait(10) and sent.result().accepted
            cancel = sent.result().cancel_goal_async()
            assert cancel.wait(5) and len(cancel.result().goals_canceling) == 1, cancel.result()
            done = sent.result().get_result_async()
            assert done.wait(10) and done.result().status == GoalStatus.CANCELED
    finally:
        executor.shutdown()
        thread.join(timeout=5)


def test_cancel_service_moves_to_the_remaining_server(make_context):
    """Two action types under one name in one node share one cancel service; destroying the
    server that holds it hands it to the other."""
    from interfaces.action_tutorials_interfaces.action import Fibonacci
    from interfaces.example_interfaces.action import Fibonacci as ExampleFibonacci

    def execute(goal_handle):
        while not goal_handle.is_cancel_requested:
            time.sleep(0.01)
        goal_handle.canceled()
        return ExampleFibonacci.Result()
    server_node = Node('two_types', context=make_context())
    group = ReentrantCallbackGroup()
    first = ActionServer(server_node, Fibonacci, 'fib', execute, callback_group=group)
    second = ActionServer(server_node, ExampleFibonacci, 'fib', execute, callback_group=group,
                          cancel_callback=lambda handle: CancelResponse.ACCEPT)
    assert first._cancel_service is not None and second._cancel_service is None
    first.destroy()
    assert second._cancel_service is not None
    server_exec = MultiThreadedExecutor(context=server_node.context)
    server_exec.add_node(server_node)
    client_ctx = make_context()
    client_node = Node('two_types_client', context=client_ctx)
    client_exec = MultiThreadedExecutor(context=client_ctx)
    client_exec.add_node(client_node)
    threads = [threading.Thread(target=e.spin, daemon=True) for e in (server_exec, client_exec)]
    for t in threads:
        t.start()
    try:
        client = ActionClient(client_node, ExampleFibonacci, 'fib')
        assert client.wait_for_server(timeout_sec=10)
        sent = client.send_goal_async(ExampleFibonacci.Goal(order=3))
        assert sent.wait(10) and sent.result().accepted
        cancel = sent.result().cancel_goal_async()
        assert cancel.wait(5) and len(cancel.result().goals_canceling) == 1
    finally:
        for e in (server_exec, client_exec):
            e.shutdown()
        for t in threads:
            t.join(timeout=5)
