"""launch_ros's Node under a LaunchService started from code, as launch_ros's users and tests
run it: a node whose package is missing fails the run with a return code, inline parameters
reach the node without a log directory, and talker_qos stops after its cycles."""
from __future__ import annotations

from zros.launch import LaunchDescription, LaunchService
from zros.launch_ros.actions import Node


def run(*actions) -> int:
    service = LaunchService()
    service.include_launch_description(LaunchDescription(list(actions)))
    return service.run()


def test_a_node_of_a_missing_package_fails_the_run_with_one_line(capfd):
    assert run(Node(package='no_such_package', executable='node')) == 1
    printed = capfd.readouterr()
    assert "package 'no_such_package' not found" in printed.out + printed.err   # the launch's log line


def test_inline_parameters_reach_a_node_started_by_a_launch_service(capfd):
    probe = ('import sys, yaml; i = sys.argv.index("--params-file"); '
             'print("rate =", yaml.safe_load(open(sys.argv[i + 1]))["/**"]["ros__parameters"]["rate"])')
    node = Node(executable='python3', arguments=['-c', probe], parameters=[{'rate': 7}], output='screen')
    assert run(node) == 0
    assert 'rate = 7' in capfd.readouterr().out


def test_talker_qos_stops_after_its_cycles(capfd):
    talker = Node(package='demo_nodes_py', executable='talker_qos', arguments=['--number_of_cycles', '1'],
                  name='talker', namespace='qos', output='screen')
    assert run(talker) == 0
    assert "Publishing: 'Hello World: 1'" in capfd.readouterr().out


def test_a_ros_timer_on_sim_time_fires_when_clock_has_advanced_its_period(capfd):
    """/clock advances 100 s every 0.2 s of wall time: a 300 s ROSTimer fires after about 0.6 s."""
    import threading
    import time

    import zros
    from interfaces.builtin_interfaces.msg import Time
    from interfaces.rosgraph_msgs.msg import Clock
    from zros.launch.actions import ExecuteProcess
    from zros.launch_ros.actions import ROSTimer, SetUseSimTime

    stop = threading.Event()

    def publish_clock() -> None:
        with zros.init(args=[]) as context:
            node = zros.create_node('sim_clock', context=context)
            publisher = node.create_publisher(Clock, '/clock', 10)
            seconds = 0
            while not stop.wait(0.2):
                seconds += 100
                publisher.publish(Clock(clock=Time(sec=seconds)))

    thread = threading.Thread(target=publish_clock, daemon=True)
    thread.start()
    try:
        started = time.monotonic()
        fired = ExecuteProcess(cmd=['python3', '-c', 'print("timer fired")'], output='screen')
        assert run(ROSTimer(period=300.0, actions=[fired]), SetUseSimTime(True)) == 0
        assert time.monotonic() - started < 30.0
        assert 'timer fired' in capfd.readouterr().out
    finally:
        stop.set()
        thread.join()


def test_a_ros_timer_without_sim_time_is_a_wall_clock_timer():
    import time

    from zros.launch_ros.actions import ROSTimer
    started = time.monotonic()
    assert run(ROSTimer(period=0.5, actions=[])) == 0
    assert time.monotonic() - started >= 0.5


def run_for(seconds: float, *actions) -> int:
    """Run `actions` under run_async for `seconds`, then shut down from the loop, as launch_ros's
    tests drive nodes that never end by themselves."""
    import asyncio
    service = LaunchService()
    service.include_launch_description(LaunchDescription(list(actions)))
    loop = asyncio.new_event_loop()
    try:
        task = loop.create_task(service.run_async())
        loop.run_until_complete(asyncio.sleep(seconds))
        assert not task.done()
        loop.create_task(service.shutdown())
        return loop.run_until_complete(task)
    finally:
        loop.close()


def test_composition_components_and_listener_qos_hear_the_chatter(capfd):
    from zros.launch_ros.actions import ComposableNodeContainer
    from zros.launch_ros.descriptions import ComposableNode
    container = ComposableNodeContainer(
        package='rclcpp_components', executable='component_container', name='box', namespace='',
        composable_node_descriptions=[ComposableNode(package='composition', plugin='composition::Talker'),
                                      ComposableNode(package='composition', plugin='composition::Listener')],
        output='screen')
    listener = Node(package='demo_nodes_py', executable='listener_qos', output='screen')
    assert run_for(6.0, container, listener) == 0
    out = capfd.readouterr().out
    assert 'Best effort listener' in out
    assert "Publishing: 'Hello World: " in out and 'I heard: [Hello World: ' in out
    heard_by = {line.split(']')[0] for line in out.splitlines() if 'I heard: [Hello World' in line}
    assert {'[listener-2', '[listener_qos-3'} <= heard_by, out


def test_lifecycle_listener_reports_the_talkers_transitions(capfd):
    from zros.launch.actions import EmitEvent
    from zros.launch.events import matches_action
    from zros.launch_ros.actions import LifecycleNode
    from zros.launch_ros.events.lifecycle import ChangeState
    from interfaces.lifecycle_msgs.msg import Transition
    talker = LifecycleNode(package='lifecycle', executable='lifecycle_talker', name='lc_talker', namespace='',
                           output='screen')
    listener = Node(package='lifecycle', executable='lifecycle_listener', output='screen')
    configure = EmitEvent(event=ChangeState(lifecycle_node_matcher=matches_action(talker),
                                            transition_id=Transition.TRANSITION_CONFIGURE))
    assert run_for(6.0, listener, talker, configure) == 0
    assert 'notify callback: Transition from state unconfigured to configuring' in capfd.readouterr().out
