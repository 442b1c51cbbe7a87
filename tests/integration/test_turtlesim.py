"""turtlesim: turtlesim_node, teleop, draw_square and mimic as real processes over zros (the
pymunk world on its own: tests/unit/test_turtlesim_world.py).

One turtlesim_node serves the node-level tests of this module (each test starts with /reset),
so the whole file stays well under a minute on two cores.
"""
from __future__ import annotations

import math
import os
import subprocess
import sys
import threading
import time
from typing import Any, Callable

import numpy as np
import pytest

from nodes.turtlesim._world import WORLD_SIZE
from conftest import REPO, assert_clean_failure, wait_until
from unit.test_turtlesim_world import BACKGROUND, CENTER


# -- the world, without zros --------------------------------------------------------------------


# -- turtlesim_node over zros --------------------------------------------------------------------
class Sim:
    """A test-side node talking to the module's turtlesim_node."""

    def __init__(self, child: Any, node: Any) -> None:
        from interfaces.turtlesim.msg import Pose
        self.child = child
        self.node = node
        self.poses: list[Any] = []
        self._pose_lock = threading.Lock()
        node.create_subscription(Pose, '/turtle1/pose', self._on_pose, 10)
        self._clients: dict[str, Any] = {}

    def _on_pose(self, pose: Any) -> None:
        with self._pose_lock:
            self.poses.append(pose)
            del self.poses[:-200]

    @property
    def pose(self) -> Any:
        with self._pose_lock:
            return self.poses[-1] if self.poses else None

    def wait_pose(self, predicate: Callable[[Any], bool], timeout: float = 5.0, what: str = 'pose') -> Any:
        return wait_until(lambda: self.pose is not None and predicate(self.pose) and self.pose, timeout,
                          message=lambda: f'{what}; last pose {self.pose}')

    def call(self, srv_type: type, service: str, timeout: float = 5.0, **fields: Any) -> Any:
        client = self._clients.get(service)
        if client is None:
            client = self._clients[service] = self.node.create_client(srv_type, service)
            assert client.wait_for_service(timeout_sec=10), f'no service {service}'
        return client.call(srv_type.Request(**fields), timeout_sec=timeout)

    def reset(self) -> None:
        from interfaces.std_srvs.srv import Empty
        self.call(Empty, '/reset')
        self.wait_pose(lambda p: abs(p.x - CENTER) < 1e-3 and abs(p.y - CENTER) < 1e-3 and p.theta == 0.0
                       and p.linear_velocity == 0.0, what='turtle1 back in the middle')

    def twist(self, linear: float = 0.0, angular: float = 0.0, topic: str = '/turtle1/cmd_vel',
              linear_y: float = 0.0) -> None:
        from interfaces.geometry_msgs.msg import Twist
        pub = self._clients.get(topic)
        if pub is None:
            pub = self._clients[topic] = self.node.create_publisher(Twist, topic, 10)
            wait_until(lambda: pub.get_subscription_count() > 0, 5, message=f'a subscriber on {topic}')
        msg = Twist()
        msg.linear.x, msg.linear.y, msg.angular.z = linear, linear_y, angular
        pub.publish(msg)

    def frames(self) -> 'Frames':
        return Frames(self.node)


class Frames:
    """Subscribes to /turtlesim/image while in its `with` block."""

    def __init__(self, node: Any) -> None:
        self.node, self.latest, self.count = node, None, 0

    def __enter__(self) -> 'Frames':
        from interfaces.sensor_msgs.msg import Image
        from zros.qos import qos_profile_sensor_data
        self.sub = self.node.create_subscription(Image, '/turtlesim/image', self._on_image, qos_profile_sensor_data)
        return self

    def _on_image(self, msg: Any) -> None:
        assert (msg.height, msg.width, msg.encoding, msg.step) == (500, 500, 'rgb8', 1500)
        self.latest = np.asarray(msg.data, dtype=np.uint8).reshape(500, 500, 3).copy()
        self.count += 1

    def wait(self, predicate: Callable[[np.ndarray], bool], timeout: float = 5.0, what: str = 'frame') -> np.ndarray:
        def check() -> Any:
            frame = self.latest
            return frame is not None and predicate(frame) and (frame,)
        return wait_until(check, timeout, message=what)[0]

    def __exit__(self, *exc: object) -> None:
        self.node.destroy_subscription(self.sub)


def _px(x: float, y: float) -> tuple[int, int]:
    """(row, column) of the canvas pixel under world point (x, y)."""
    return int(round((WORLD_SIZE - y) * 45.0)), int(round(x * 45.0))


@pytest.fixture(scope='module')
def sim(module_domain, module_spawn):
    from zros.context import Context
    from zros.executors import MultiThreadedExecutor
    from zros.node import Node
    child = module_spawn.node('turtlesim', 'turtlesim_node')
    ctx = Context().init([], install_signal_handlers=False)
    node = Node('turtlesim_test', context=ctx)
    executor = MultiThreadedExecutor(context=ctx)
    executor.add_node(node)
    thread = threading.Thread(target=_spin, args=(executor,), daemon=True)
    thread.start()
    harness = Sim(child, node)
    child.wait_for_output('Spawning turtle [turtle1] at x=[5.544444], y=[5.544444], theta=[0.000000]', 20)
    assert 'Starting turtlesim with node name /turtlesim' in child.output()
    yield harness
    executor.shutdown(timeout_sec=2)
    ctx.shutdown()


def _spin(executor: Any) -> None:
    try:
        executor.spin()
    except Exception:  # noqa: BLE001 - ends with the context
        pass


def test_node_graph_matches_ros(sim):
    from zros.graph import EntityKind
    expected = {
        EntityKind.PUBLISHER: {'/turtle1/pose': 'turtlesim/msg/Pose', '/turtle1/color_sensor': 'turtlesim/msg/Color',
                               '/turtlesim/image': 'sensor_msgs/msg/Image'},
        EntityKind.SUBSCRIPTION: {'/turtle1/cmd_vel': 'geometry_msgs/msg/Twist'},
        EntityKind.SERVICE: {'/spawn': 'turtlesim/srv/Spawn', '/kill': 'turtlesim/srv/Kill',
                             '/clear': 'std_srvs/srv/Empty', '/reset': 'std_srvs/srv/Empty',
                             '/turtle1/set_pen': 'turtlesim/srv/SetPen',
                             '/turtle1/teleport_absolute': 'turtlesim/srv/TeleportAbsolute',
                             '/turtle1/teleport_relative': 'turtlesim/srv/TeleportRelative'},
        EntityKind.ACTION_SERVER: {'/turtle1/rotate_absolute': 'turtlesim/action/RotateAbsolute'},
    }

    def complete() -> bool:
        found = {(e.kind, e.name, e.type) for e in sim.node.context.graph.entities() if e.node_name == 'turtlesim'}
        return all((kind, name, typ) in found for kind, names in expected.items() for name, typ in names.items())
    wait_until(complete, 5, message='turtlesim entities in the graph')
    pose = sim.wait_pose(lambda p: True)
    assert (pose.x, pose.y) == (pytest.approx(CENTER, abs=1e-4), pytest.approx(CENTER, abs=1e-4))


def test_param_list_matches_ros(sim, zros_cli):
    """`ros2 param list /turtlesim` on Jazzy (the C++ node's qos_overrides and the
    start_type_description_service every node declares, as seed 002 lists them), and the
    failure a node gives for a read-only one, with its reason, as ros2 param set prints it."""
    listed = zros_cli('param', 'list', '/turtlesim')
    assert listed.returncode == 0, listed
    assert listed.stdout.splitlines() == [
        '/turtlesim:', '  background_b', '  background_g', '  background_r', '  holonomic',
        '  qos_overrides./parameter_events.publisher.depth',
        '  qos_overrides./parameter_events.publisher.durability',
        '  qos_overrides./parameter_events.publisher.history',
        '  qos_overrides./parameter_events.publisher.reliability', '  start_type_description_service',
        '  use_sim_time'], listed
    depth = zros_cli('param', 'get', '/turtlesim', 'qos_overrides./parameter_events.publisher.depth')
    assert depth.stdout == 'Integer value is: 1000\n', depth
    refused = zros_cli('param', 'set', '/turtlesim', 'qos_overrides./parameter_events.publisher.depth', '5')
    assert_clean_failure(refused, 'Setting parameter failed: Trying to set a read-only parameter: '
                                  'qos_overrides./parameter_events.publisher.depth')


def test_teleport_absolute_and_relative(sim):
    from interfaces.turtlesim.srv import TeleportAbsolute, TeleportRelative
    sim.reset()
    sim.call(TeleportAbsolute, '/turtle1/teleport_absolute', x=2.0, y=3.0, theta=0.5)
    sim.wait_pose(lambda p: abs(p.x - 2.0) < 1e-4 and abs(p.y - 3.0) < 1e-4 and abs(p.theta - 0.5) < 1e-4)
    sim.call(TeleportRelative, '/turtle1/teleport_relative', linear=1.0, angular=0.5)
    sim.wait_pose(lambda p: abs(p.x - (2.0 + math.cos(1.0))) < 1e-4 and abs(p.y - (3.0 + math.sin(1.0))) < 1e-4
                  and abs(p.theta - 1.0) < 1e-4, what='the relative teleport')


def test_spawn_duplicate_and_kill(sim):
    from interfaces.turtlesim.srv import Kill, Spawn
    from zros.errors import ServiceCallError
    sim.reset()
    assert sim.call(Spawn, '/spawn', x=2.0, y=2.0, theta=0.0).name == 'turtle2'
    wait_until(lambda: sim.node.count_publishers('/turtle2/pose') == 1, 5, message='/turtle2/pose')
    wait_until(lambda: sim.node.count_services('/turtle2/set_pen') == 1, 5, message='/turtle2/set_pen')
    with pytest.raises(ServiceCallError, match=r'A turtle named \[turtle2\] already exists'):
        sim.call(Spawn, '/spawn', x=1.0, y=1.0, theta=0.0, name='turtle2')
    assert sim.call(Spawn, '/spawn', x=1.0, y=1.0, theta=0.0, name='leonardo').name == 'leonardo'
    sim.call(Kill, '/kill', name='turtle2')
    wait_until(lambda: sim.node.count_publishers('/turtle2/pose') == 0, 5, message='/turtle2/pose to go')
    with pytest.raises(ServiceCallError, match=r'Tried to kill turtle \[turtle2\], which does not exist'):
        sim.call(Kill, '/kill', name='turtle2')
    assert sim.child.output().count('Spawning turtle [leonardo] at x=[1.000000], y=[1.000000]') == 1
    sim.reset()
    wait_until(lambda: sim.node.count_publishers('/leonardo/pose') == 0, 5, message='reset to remove leonardo')


def test_pen_colour_appears_pen_off_draws_nothing_and_clear(sim):
    from interfaces.std_srvs.srv import Empty
    from interfaces.turtlesim.srv import SetPen, TeleportAbsolute
    sim.reset()
    with sim.frames() as frames:
        frames.wait(lambda f: tuple(f[_px(8.0, CENTER)]) == BACKGROUND, what='a clean canvas')
        sim.call(SetPen, '/turtle1/set_pen', r=255, g=0, b=0, width=6, off=0)
        sim.call(TeleportAbsolute, '/turtle1/teleport_absolute', x=2.0, y=CENTER, theta=0.0)
        frames.wait(lambda f: tuple(f[_px(3.7, CENTER)]) == (255, 0, 0), what='a red line')
        sim.call(SetPen, '/turtle1/set_pen', r=0, g=255, b=0, width=6, off=1)
        sim.call(TeleportAbsolute, '/turtle1/teleport_absolute', x=2.0, y=1.0, theta=0.0)
        sim.wait_pose(lambda p: abs(p.y - 1.0) < 1e-4)
        frame = frames.wait(lambda f: tuple(f[_px(2.0, 1.0)]) != BACKGROUND, what='the turtle drawn at (2, 1)')
        column = frame[_px(2.0, CENTER - 0.6)[0]:_px(2.0, 2.0)[0], _px(2.0, 0)[1]]
        assert (column == BACKGROUND).all(), 'the pen was off, yet the move left a trail'
        sim.call(Empty, '/clear')
        frames.wait(lambda f: tuple(f[_px(3.7, CENTER)]) == BACKGROUND, what='clear to remove the line')


def test_background_parameter_repaints_live(sim):
    from interfaces.rcl_interfaces.msg import Parameter, ParameterType, ParameterValue
    from interfaces.rcl_interfaces.srv import SetParameters

    def set_red(value: int) -> None:
        response = sim.call(SetParameters, '/turtlesim/set_parameters', parameters=[Parameter(
            name='background_r', value=ParameterValue(type=ParameterType.PARAMETER_INTEGER, integer_value=value))])
        assert response.results[0].successful, response.results[0].reason

    sim.reset()
    with sim.frames() as frames:
        frames.wait(lambda f: tuple(f[5, 5]) == BACKGROUND, what='the default background')
        set_red(150)
        try:
            frames.wait(lambda f: tuple(f[5, 5]) == (150, 86, 255), what='the new background')
        finally:
            set_red(BACKGROUND[0])


def test_color_sensor_reports_the_colour_underneath(sim):
    from interfaces.turtlesim.msg import Color
    from interfaces.turtlesim.srv import SetPen, TeleportAbsolute
    colours: list[Any] = []
    sub = sim.node.create_subscription(Color, '/turtle1/color_sensor', colours.append, 10)
    try:
        sim.reset()
        wait_until(lambda: colours and (colours[-1].r, colours[-1].g, colours[-1].b) == BACKGROUND, 5,
                   message='the background colour under turtle1')
        sim.call(SetPen, '/turtle1/set_pen', r=10, g=200, b=30, width=10, off=0)
        sim.call(TeleportAbsolute, '/turtle1/teleport_absolute', x=2.0, y=CENTER, theta=0.0)
        wait_until(lambda: (colours[-1].r, colours[-1].g, colours[-1].b) == (10, 200, 30), 5,
                   message='the pen colour under turtle1')
    finally:
        sim.node.destroy_subscription(sub)


def test_cmd_vel_older_than_one_second_stops_the_turtle(sim):
    sim.reset()
    sim.twist(linear=1.0)
    sim.wait_pose(lambda p: p.linear_velocity == 1.0, what='the turtle to move')
    stopped = sim.wait_pose(lambda p: p.linear_velocity == 0.0 and p.x > CENTER + 0.5, timeout=3,
                            what='the command to expire')
    assert stopped.x - CENTER == pytest.approx(1.0, abs=0.05)
    time.sleep(0.3)
    assert sim.pose.x == pytest.approx(stopped.x, abs=1e-6)


def test_wall_stops_the_turtle_and_warns(sim):
    from interfaces.turtlesim.srv import TeleportAbsolute
    sim.reset()
    sim.call(TeleportAbsolute, '/turtle1/teleport_absolute', x=10.5, y=3.0, theta=0.0)
    sim.wait_pose(lambda p: abs(p.x - 10.5) < 1e-4)
    sim.twist(linear=3.0)
    pose = sim.wait_pose(lambda p: p.x > WORLD_SIZE - 0.01, what='the turtle at the wall')
    sim.child.wait_for_output('Oh no! I hit the wall! (Clamping from [x=11.', 5)
    time.sleep(0.2)
    assert sim.pose.x <= WORLD_SIZE + 1e-6 and sim.pose.y == pytest.approx(3.0, abs=1e-4)
    assert pose.x == pytest.approx(WORLD_SIZE, abs=2e-3)


def test_holonomic_parameter_allows_sideways_motion(sim):
    from interfaces.rcl_interfaces.msg import Parameter, ParameterType, ParameterValue
    from interfaces.rcl_interfaces.srv import SetParameters

    def set_holonomic(value: bool) -> None:
        sim.call(SetParameters, '/turtlesim/set_parameters', parameters=[Parameter(
            name='holonomic', value=ParameterValue(type=ParameterType.PARAMETER_BOOL, bool_value=value))])

    sim.reset()
    sim.twist(linear_y=1.0)  # ignored: not holonomic
    time.sleep(0.3)
    assert sim.pose.y == pytest.approx(CENTER, abs=1e-6)
    set_holonomic(True)
    try:
        sim.twist(linear_y=1.0)
        sim.wait_pose(lambda p: p.y > CENTER + 0.2, what='sideways motion')
        assert sim.pose.x == pytest.approx(CENTER, abs=1e-6)
    finally:
        set_holonomic(False)


def _rotate_client(sim: Sim) -> Any:
    from interfaces.turtlesim.action import RotateAbsolute
    from zros.action import ActionClient
    client = getattr(sim, '_rotate', None)
    if client is None:
        client = sim._rotate = ActionClient(sim.node, RotateAbsolute, '/turtle1/rotate_absolute')
        assert client.wait_for_server(timeout_sec=10)
    return client


def _send_goal(sim: Sim, theta: float, feedback: list | None = None) -> Any:
    from interfaces.turtlesim.action import RotateAbsolute
    future = _rotate_client(sim).send_goal_async(RotateAbsolute.Goal(theta=theta),
                                                feedback_callback=None if feedback is None else feedback.append)
    assert future.wait(5), 'no answer to the goal'
    handle = future.result()
    assert handle.accepted
    return handle


def test_rotate_absolute_reaches_the_angle_with_feedback(sim):
    from zros.action.server import GoalStatus
    sim.reset()
    feedback: list[Any] = []
    handle = _send_goal(sim, 1.0, feedback)
    result = handle.get_result_async()
    assert result.wait(5)
    response = result.result()
    assert response.status == GoalStatus.SUCCEEDED
    assert response.result.delta == pytest.approx(-1.0, abs=0.03)  # ROS: start minus end
    remaining = [f.feedback.remaining for f in feedback]
    assert len(remaining) > 20 and remaining[0] > 0.9 and abs(remaining[-1]) < 0.05
    assert all(a >= b - 1e-6 for a, b in zip(remaining, remaining[1:]))
    pose = sim.wait_pose(lambda p: p.angular_velocity == 0.0)
    assert pose.theta == pytest.approx(1.0, abs=0.02)
    sim.child.wait_for_output('Rotation goal completed successfully', 2)


def test_rotate_absolute_cancel(sim):
    from zros.action.server import GoalStatus
    sim.reset()
    handle = _send_goal(sim, -2.5)
    sim.wait_pose(lambda p: p.theta < -0.2, what='the turn to start')
    cancel = handle.cancel_goal_async()
    assert cancel.wait(5) and len(cancel.result().goals_canceling) == 1
    result = handle.get_result_async()
    assert result.wait(5) and result.result().status == GoalStatus.CANCELED
    pose = sim.wait_pose(lambda p: p.angular_velocity == 0.0, what='the turtle to stop turning')
    assert -2.0 < pose.theta < -0.2
    sim.child.wait_for_output('Rotation goal canceled', 2)


def test_rotate_absolute_new_goal_preempts_the_old(sim):
    from zros.action.server import GoalStatus
    sim.reset()
    first = _send_goal(sim, 2.5)
    sim.wait_pose(lambda p: p.theta > 0.2, what='the first turn to start')
    second = _send_goal(sim, 0.0)
    first_result, second_result = first.get_result_async(), second.get_result_async()
    assert first_result.wait(5) and first_result.result().status == GoalStatus.ABORTED
    assert second_result.wait(5) and second_result.result().status == GoalStatus.SUCCEEDED
    assert abs(sim.wait_pose(lambda p: p.angular_velocity == 0.0).theta) < 0.02
    sim.child.wait_for_output('Rotation goal received before a previous goal finished. Aborting previous goal', 2)
    # A velocity command aborts a running goal too.
    third = _send_goal(sim, -2.5)
    sim.wait_pose(lambda p: p.theta < -0.2, what='the third turn to start')
    sim.twist(linear=0.0)
    third_result = third.get_result_async()
    assert third_result.wait(5) and third_result.result().status == GoalStatus.ABORTED
    sim.child.wait_for_output('Velocity command received during rotation goal. Aborting goal', 2)


def test_reset_restores_the_initial_state(sim):
    from interfaces.std_srvs.srv import Empty
    from interfaces.turtlesim.srv import Spawn, TeleportAbsolute
    sim.reset()
    sim.call(Spawn, '/spawn', x=2.0, y=2.0, theta=0.0)
    sim.call(TeleportAbsolute, '/turtle1/teleport_absolute', x=1.0, y=1.0, theta=1.0)
    sim.wait_pose(lambda p: abs(p.x - 1.0) < 1e-4)
    with sim.frames() as frames:
        frames.wait(lambda f: tuple(f[_px(3.0, 3.0)]) != BACKGROUND, what='the teleport trail')
        sim.call(Empty, '/reset')
        sim.wait_pose(lambda p: abs(p.x - CENTER) < 1e-4 and p.theta == 0.0)
        frames.wait(lambda f: tuple(f[_px(3.0, 3.0)]) == BACKGROUND, what='reset to clear the canvas')
    wait_until(lambda: sim.node.count_publishers('/turtle2/pose') == 0, 5, message='reset to remove turtle2')
    from interfaces.turtlesim.srv import Spawn as SpawnAgain
    assert sim.call(SpawnAgain, '/spawn', x=2.0, y=2.0, theta=0.0).name == 'turtle2'  # counter restarted
    sim.reset()


def test_mimic_copies_the_motion(sim, module_spawn):
    from interfaces.turtlesim.msg import Pose
    from interfaces.turtlesim.srv import Spawn
    sim.reset()
    sim.call(Spawn, '/spawn', x=2.0, y=2.0, theta=0.0, name='copycat')
    copies: list[Any] = []
    sub = sim.node.create_subscription(Pose, '/copycat/pose', copies.append, 10)
    mimic = module_spawn.node('turtlesim', 'mimic', '--ros-args', '-r', 'input/pose:=/turtle1/pose',
                              '-r', 'output/cmd_vel:=/copycat/cmd_vel')
    try:
        wait_until(lambda: sim.node.count_subscribers('/copycat/cmd_vel') >= 1
                   and sim.node.count_publishers('/copycat/cmd_vel') >= 1, 10, message='mimic in the graph')
        sim.twist(linear=1.5, angular=0.5)
        wait_until(lambda: copies and copies[-1].linear_velocity == 1.5 and copies[-1].angular_velocity == 0.5, 5,
                   message='the copy to move like turtle1')
    finally:
        mimic.kill()
        sim.node.destroy_subscription(sub)
        sim.reset()


def test_draw_square_resets_and_drives(sim, module_spawn):
    from interfaces.turtlesim.srv import TeleportAbsolute
    sim.call(TeleportAbsolute, '/turtle1/teleport_absolute', x=1.0, y=1.0, theta=0.0)
    sim.wait_pose(lambda p: abs(p.x - 1.0) < 1e-4)
    child = module_spawn.node('turtlesim', 'draw_square')
    try:
        child.wait_for_output('New goal [', 10)
        sim.wait_pose(lambda p: p.x > CENTER + 0.5 and abs(p.y - CENTER) < 0.01, timeout=5,
                      what='the first side of the square, from the reset turtle')
        child.wait_for_output('Reached goal', 5)
    finally:
        child.kill()
        sim.reset()


def test_teleop_key_through_a_pty(sim):
    import termios
    from interfaces.geometry_msgs.msg import Twist
    twists: list[Any] = []
    sub = sim.node.create_subscription(Twist, '/turtle1/cmd_vel', twists.append, 10)
    sim.reset()
    master, slave = os.openpty()
    before = termios.tcgetattr(slave)
    proc = subprocess.Popen([sys.executable, '-m', 'zros.cli.main', 'run', 'turtlesim', 'turtle_teleop_key'],
                            stdin=slave, stdout=slave, stderr=slave, cwd=REPO, env=dict(os.environ),
                            start_new_session=True)
    screen = bytearray()

    def read_screen() -> str:
        import select
        while select.select([master], [], [], 0)[0]:
            try:
                screen.extend(os.read(master, 4096))
            except OSError:
                break
        return screen.decode(errors='replace')
    try:
        wait_until(lambda: "'q' to quit." in read_screen(), 15, message=lambda: f'the instructions; got {read_screen()!r}')
        text = read_screen()
        assert 'Reading from keyboard\r\n---------------------------\r\nUse arrow keys to move the turtle.' in text
        assert "Use g|b|v|c|d|e|r|t keys to rotate to absolute orientations. 'f' to cancel a rotation." in text
        during = termios.tcgetattr(slave)
        assert not during[3] & termios.ICANON and not during[3] & termios.ECHO
        wait_until(lambda: sim.node.count_subscribers('/turtle1/cmd_vel') >= 1
                   and sim.node.count_publishers('/turtle1/cmd_vel') >= 1, 10, message='teleop in the graph')
        time.sleep(0.3)
        os.write(master, b'\x1b[A')   # up arrow
        wait_until(lambda: twists and twists[-1].linear.x == 2.0 and twists[-1].angular.z == 0.0, 5,
                   message=lambda: f'Twist(linear.x=2) from the up arrow; got {twists[-1:]}')
        sim.wait_pose(lambda p: p.linear_velocity == 2.0, what='turtle1 to drive')
        os.write(master, b'\x1b[D')   # left arrow
        wait_until(lambda: twists[-1].angular.z == 2.0 and twists[-1].linear.x == 0.0, 5,
                   message='Twist(angular.z=2) from the left arrow')
        sim.wait_pose(lambda p: p.linear_velocity == 0.0 and p.angular_velocity == 0.0, timeout=3)
        count = len(twists)
        os.write(master, b'r')        # rotate to pi/2 through the action
        pose = sim.wait_pose(lambda p: abs(p.theta - 1.5708) < 0.02 and p.angular_velocity == 0.0, timeout=6,
                             what="the 'r' key's rotation to pi/2")
        assert len(twists) == count, 'a rotation key must use the action, not cmd_vel'
        assert pose.x != CENTER  # it had moved forward with the up arrow
        os.write(master, b'q')
        assert proc.wait(timeout=10) == 0
        after = termios.tcgetattr(slave)
        assert after[3] == before[3], 'the terminal mode was not restored'
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, 9)
            proc.wait(timeout=5)
        os.close(master)
        os.close(slave)
        sim.node.destroy_subscription(sub)


def test_teleop_key_restores_the_terminal_on_ctrl_c(domain):
    import fcntl
    import select
    import termios
    master, slave = os.openpty()
    before = termios.tcgetattr(slave)

    def controlling_terminal() -> None:  # so that ^C becomes SIGINT, as in a real terminal
        os.setsid()
        fcntl.ioctl(0, termios.TIOCSCTTY, 0)
    proc = subprocess.Popen([sys.executable, '-m', 'zros.cli.main', 'run', 'turtlesim', 'turtle_teleop_key'],
                            stdin=slave, stdout=slave, stderr=slave, cwd=REPO, env=dict(os.environ),
                            preexec_fn=controlling_terminal)
    screen = bytearray()

    def read_screen() -> str:
        while select.select([master], [], [], 0)[0]:
            try:
                screen.extend(os.read(master, 4096))
            except OSError:
                break
        return screen.decode(errors='replace')
    try:
        wait_until(lambda: "'q' to quit." in read_screen(), 15, message=lambda: f'the instructions; got {read_screen()!r}')
        assert not termios.tcgetattr(slave)[3] & termios.ECHO
        os.write(master, b'\x03')
        assert proc.wait(timeout=10) == 0
        assert termios.tcgetattr(slave)[3] == before[3], 'the terminal mode was not restored after Ctrl-C'
        assert 'Traceback' not in read_screen()
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait(timeout=5)
        os.close(master)
        os.close(slave)
