"""turtlebot3_gazebo gzserver as a real process over zros: topics, QoS, rates in simulated time,
driving, odometry, the lidar, collisions, Gazebo's services, namespaces, bad input.

One gzserver (turtlebot3_world, started paused) serves most tests: each resets it and moves
time itself with the ControlWorld step service, so results are exact and nothing waits on the
wall clock. Tests that need other start-up parameters start their own.
"""
from __future__ import annotations

import math
import threading
import time
from typing import Any, Callable

import numpy as np
import pytest

from conftest import assert_clean_failure, wait_until
from zros.sim import BURGER, LDS_01, load_world
from zros.sim.raycast import cast_fan

WORLD = 'turtlebot3_world'
SPAWN = (-2.0, -0.5)
STEP = 0.005          # the simulator's physics step [s]
SETTLE = 0.5          # [s] of wall time for a published command to reach the paused simulator


class Harness:
    """A test-side node: subscriptions that record, cached clients and publishers."""

    def __init__(self, node: Any, child: Any) -> None:
        self.node, self.child = node, child
        self.messages: dict[str, list[Any]] = {}
        self._lock = threading.Lock()
        self._clients: dict[str, Any] = {}
        self._publishers: dict[str, Any] = {}

    def record(self, msg_type: type, topic: str, qos: Any = 1000) -> list[Any]:
        """Keep what arrives on `topic` (deep by default: stepping publishes in bursts)."""
        if topic not in self.messages:
            messages = self.messages[topic] = []

            def keep(msg: Any) -> None:
                with self._lock:
                    messages.append(msg)
            self.node.create_subscription(msg_type, topic, keep, qos)
        return self.messages[topic]

    def clear(self) -> None:
        with self._lock:
            for messages in self.messages.values():
                messages.clear()

    def call(self, srv_type: type, service: str, timeout: float = 10.0, **fields: Any) -> Any:
        client = self._clients.get(service)
        if client is None:
            client = self._clients[service] = self.node.create_client(srv_type, service)
            assert client.wait_for_service(timeout_sec=15), f'no service {service}'
        return client.call(srv_type.Request(**fields), timeout_sec=timeout)

    def publish(self, msg: Any, topic: str) -> None:
        pub = self._publishers.get(topic)
        if pub is None:
            pub = self._publishers[topic] = self.node.create_publisher(type(msg), topic, 10)
            wait_until(lambda: pub.get_subscription_count() > 0, 10, message=f'a subscriber on {topic}')
        pub.publish(msg)

    def twist(self, linear: float, angular: float = 0.0, topic: str = '/cmd_vel', settle: bool = True) -> None:
        """Publish a Twist; with `settle`, give it time to reach the (paused) simulator."""
        from interfaces.geometry_msgs.msg import Twist
        msg = Twist()
        msg.linear.x, msg.angular.z = linear, angular
        self.publish(msg, topic)
        if settle:
            time.sleep(SETTLE)

    def step(self, seconds: float) -> None:
        from interfaces.ros_gz_interfaces.srv import ControlWorld
        request = ControlWorld.Request()
        request.world_control.pause = True
        request.world_control.multi_step = int(round(seconds / STEP))
        assert self.call(ControlWorld, f'/world/{WORLD}/control', timeout=30, world_control=request.world_control).success

    def state(self, name: str = 'burger') -> tuple[float, float, float, float]:
        """Ground truth (x, y, yaw, forward speed) from /get_entity_state."""
        from interfaces.gazebo_msgs.srv import GetEntityState
        response = self.call(GetEntityState, '/get_entity_state', name=name)
        assert response.success, f'no entity {name}'
        p, q, v = response.state.pose.position, response.state.pose.orientation, response.state.twist.linear
        yaw = 2.0 * math.atan2(q.z, q.w)
        return p.x, p.y, math.remainder(yaw, 2 * math.pi), v.x * math.cos(yaw) + v.y * math.sin(yaw)

    def reset(self) -> None:
        from interfaces.std_srvs.srv import Empty
        self.twist(0.0)
        self.call(Empty, '/reset_simulation')
        self.clear()

    def wait(self, topic: str, predicate: Callable[[list[Any]], Any], timeout: float = 10.0, what: str = '') -> Any:
        return wait_until(lambda: predicate(list(self.messages[topic])), timeout,
                          message=lambda: f'{what or topic}; {len(self.messages[topic])} messages so far')


def _start_harness(spawner: Any, *params: str) -> tuple[Any, Any, Any]:
    from zros.context import Context
    from zros.executors import MultiThreadedExecutor
    from zros.node import Node
    args = ['--ros-args']
    for param in params:
        args += ['-p', param]
    child = spawner.node('turtlebot3_gazebo', 'gzserver', *args)
    ctx = Context().init([], install_signal_handlers=False)
    node = Node('sim_test', context=ctx)
    executor = MultiThreadedExecutor(context=ctx)
    executor.add_node(node)
    threading.Thread(target=_spin, args=(executor,), daemon=True).start()
    return Harness(node, child), executor, ctx


def _spin(executor: Any) -> None:
    try:
        executor.spin()
    except Exception:  # noqa: BLE001 - ends with the context
        pass


@pytest.fixture(scope='module')
def sim(module_domain: int, module_spawn: Any) -> Harness:
    harness, executor, ctx = _start_harness(module_spawn, f'world:={WORLD}', 'paused:=true')
    harness.child.wait_for_output("World 'turtlebot3_world' from", 30)
    assert "Spawned burger 'burger' at x=-2 y=-0.5 yaw=0" in harness.child.output()
    yield harness
    executor.shutdown(timeout_sec=2)
    ctx.shutdown()


@pytest.fixture
def fresh(sim: Harness) -> Harness:
    sim.reset()
    return sim


def test_topics_types_qos_and_services_are_the_robots(sim: Harness) -> None:
    from zros.graph import EntityKind
    node = sim.node
    expected_services = {
        '/reset_simulation': ['std_srvs/srv/Empty'], '/reset_world': ['std_srvs/srv/Empty'],
        '/pause_physics': ['std_srvs/srv/Empty'], '/unpause_physics': ['std_srvs/srv/Empty'],
        '/spawn_entity': ['gazebo_msgs/srv/SpawnEntity'], '/delete_entity': ['gazebo_msgs/srv/DeleteEntity'],
        '/get_entity_state': ['gazebo_msgs/srv/GetEntityState'],
        '/set_entity_state': ['gazebo_msgs/srv/SetEntityState'], '/get_model_list': ['gazebo_msgs/srv/GetModelList'],
        f'/world/{WORLD}/control': ['ros_gz_interfaces/srv/ControlWorld'], '/sim/get_map': ['nav_msgs/srv/GetMap']}
    expected_topics = {
        '/clock': 'rosgraph_msgs/msg/Clock', '/cmd_vel': 'geometry_msgs/msg/Twist',
        '/scan': 'sensor_msgs/msg/LaserScan', '/odom': 'nav_msgs/msg/Odometry', '/tf': 'tf2_msgs/msg/TFMessage',
        '/tf_static': 'tf2_msgs/msg/TFMessage', '/joint_states': 'sensor_msgs/msg/JointState',
        '/imu': 'sensor_msgs/msg/Imu', '/sim/ground_truth': 'nav_msgs/msg/Odometry',
        '/sim/collisions': 'std_msgs/msg/UInt32'}

    def graph() -> tuple[dict, dict]:
        topics = {name: types[0] for name, types in node.get_topic_names_and_types()}
        services = dict(node.get_service_names_and_types())
        return ({k: topics.get(k) for k in expected_topics}, {k: services.get(k) for k in expected_services})
    wait_until(lambda: graph() == (expected_topics, expected_services), 10,
               message=lambda: f'the robot\'s topics and services; got {graph()}')
    scan = node.get_publishers_info_by_topic('/scan')[0]
    assert scan.node_name == 'gazebo' and scan.qos_profile.to_token().startswith('R:V:')      # reliable, volatile
    assert any(e.kind == EntityKind.NODE and e.node_fqn == '/gazebo' for e in node.context.graph.entities())


def test_driving_0_2_m_s_for_5_s_moves_1_m_and_repeats_exactly(fresh: Harness) -> None:
    from interfaces.nav_msgs.msg import Odometry
    odoms = fresh.record(Odometry, '/odom')
    finals = []
    for attempt in range(2):        # reset_simulation reseeds: the same commands, the same run
        fresh.reset()
        assert fresh.state()[:3] == (*SPAWN, 0.0)
        fresh.twist(0.2)
        fresh.step(5.0)
        fresh.twist(0.0)
        fresh.step(1.0)
        x, y, yaw, speed = fresh.state()
        assert x - SPAWN[0] == pytest.approx(1.0, rel=0.02) and speed == 0.0
        odom = fresh.wait('/odom', lambda m: m and m[-1].header.stamp.sec == 6 and m[-1])
        finals.append((x, y, yaw, odom.pose.pose.position.x, odom.pose.pose.position.y))
    assert finals[0] == finals[1]
    # Gazebo's diff drive reports the world pose (odometry_source WORLD, the TurtleBot3's).
    assert finals[0][3:] == pytest.approx(finals[0][:2], abs=1e-9)


def test_scan_matches_the_known_walls_within_noise_and_rates_follow_sim_time(fresh: Harness) -> None:
    from interfaces.nav_msgs.msg import Odometry
    from interfaces.rosgraph_msgs.msg import Clock
    from interfaces.sensor_msgs.msg import Imu, JointState, LaserScan
    scans = fresh.record(LaserScan, '/scan', 10)        # a student's plain depth-10 subscription
    counted = {topic: fresh.record(t, topic) for topic, t in
               [('/odom', Odometry), ('/imu', Imu), ('/joint_states', JointState), ('/clock', Clock)]}
    fresh.step(2.0)
    fresh.wait('/scan', lambda m: len(m) >= 10, what='10 scans in 2 s of simulated time')
    wait_until(lambda: len(counted['/imu']) >= 400, 10, message='400 imu messages')
    scan = scans[-1]
    assert (scan.header.frame_id, len(scan.ranges), scan.angle_min, scan.angle_max) == ('base_scan', 360, 0.0,
                                                                                        pytest.approx(6.28))
    assert (scan.range_min, scan.range_max) == (pytest.approx(0.12), pytest.approx(3.5))
    stamps = [m.header.stamp.sec + m.header.stamp.nanosec * 1e-9 for m in scans]
    assert np.allclose(np.diff(stamps), 0.2)                  # 5 Hz of simulated time
    world = load_world(WORLD)
    sensor = (SPAWN[0] + BURGER.lidar_mount[0], SPAWN[1])
    expected = cast_fan(sensor, 0.0, LDS_01.angle_increment, 360, world.edges, world.circles, 3.5)
    measured = np.asarray(scan.ranges, dtype=np.float64)
    clear = np.isfinite(expected) & (expected < 3.45)
    assert np.abs(measured[clear] - expected[clear]).max() < 0.045      # 4.5 sigma
    assert np.isinf(measured[np.isinf(expected)]).all()
    assert clear.sum() > 200
    # One second of simulated time holds 30 odometry and joint-state messages and 200 imu ones.
    for topic, rate in (('/odom', 30), ('/joint_states', 30), ('/imu', 200), ('/clock', 100)):
        times = [m.clock if topic == '/clock' else m.header.stamp for m in counted[topic]]
        in_second = [t for t in times if t.sec == 1]
        assert abs(len(in_second) - rate) <= 1, (topic, len(in_second))


def test_the_tf_tree_is_the_robots(fresh: Harness) -> None:
    from zros.qos import DurabilityPolicy, QoSProfile
    from interfaces.tf2_msgs.msg import TFMessage
    static = fresh.record(TFMessage, '/tf_static', QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL))
    dynamic = fresh.record(TFMessage, '/tf', QoSProfile(depth=100))
    fresh.wait('/tf_static', lambda m: m, what='the latched /tf_static')
    fresh.step(0.1)
    fresh.wait('/tf', lambda m: m)
    edges = {(t.header.frame_id, t.child_frame_id) for t in static[-1].transforms}
    assert edges == {('base_footprint', 'base_link'), ('base_link', 'base_scan'), ('base_link', 'imu_link'),
                     ('base_link', 'caster_back_link')}
    scan_tf = next(t for t in static[-1].transforms if t.child_frame_id == 'base_scan').transform.translation
    assert (scan_tf.x, scan_tf.y, scan_tf.z) == pytest.approx((-0.032, 0.0, 0.172))
    moving = {(t.header.frame_id, t.child_frame_id) for t in dynamic[-1].transforms}
    assert moving == {('odom', 'base_footprint'), ('base_link', 'wheel_left_link'), ('base_link', 'wheel_right_link')}


def test_bad_cmd_vel_is_ignored_with_one_warning(fresh: Harness) -> None:
    fresh.twist(0.1)
    for linear, angular in ((math.nan, 0.0), (0.0, math.inf), (1e9, 0.0)):
        fresh.twist(linear, angular, settle=False)
    time.sleep(SETTLE)
    fresh.step(2.0)
    assert fresh.state()[3] == pytest.approx(0.1)          # still on the last good command
    log = fresh.child.output()
    assert log.count('Ignoring a cmd_vel') == 1 and 'Traceback' not in log
    fresh.twist(0.0)
    fresh.step(0.5)
    assert fresh.state()[3] == 0.0


def test_cmd_vel_timeout_stops_a_silent_controller(fresh: Harness) -> None:
    from zros.parameter import Parameter
    from interfaces.rcl_interfaces.srv import SetParameters
    def set_timeout(value: float) -> None:
        result = fresh.call(SetParameters, '/gazebo/set_parameters',
                            parameters=[Parameter('cmd_vel_timeout', value=value).to_parameter_msg()])
        assert result.results[0].successful
    set_timeout(0.5)
    try:
        fresh.twist(0.2)
        fresh.step(2.0)
        x, _, _, speed = fresh.state()
        assert speed == 0.0 and x - SPAWN[0] == pytest.approx(0.08, abs=0.02)   # 0.5 s less the run-up
        assert "'burger' stopped: no cmd_vel for 0.5 s (cmd_vel_timeout) at" in fresh.child.output()
    finally:
        set_timeout(0.0)


def test_collisions_are_counted_reported_and_never_pass_the_wall(fresh: Harness) -> None:
    from zros.qos import DurabilityPolicy, QoSProfile
    from interfaces.gazebo_msgs.srv import SetEntityState
    from interfaces.std_msgs.msg import UInt32
    counts = fresh.record(UInt32, '/sim/collisions', QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL))
    fresh.wait('/sim/collisions', lambda m: m and m[-1].data == 0, what='collision count 0')
    state = SetEntityState.Request().state
    state.name = 'burger'
    state.pose.position.x, state.pose.position.y = -1.6, -1.1       # 0.5 m left of a pillar, facing it
    state.pose.orientation.w = 1.0
    assert fresh.call(SetEntityState, '/set_entity_state', state=state).success
    fresh.twist(BURGER.max_linear)
    fresh.step(4.0)
    x, y, _, speed = fresh.state()
    assert math.hypot(x + 1.1, y + 1.1) > 0.15 + BURGER.body_radius - 0.0015 and speed == pytest.approx(0.0, abs=1e-3)
    fresh.wait('/sim/collisions', lambda m: m and m[-1].data == 1, what='collision count 1')
    assert "'burger' collided at x=" in fresh.child.output()
    state.pose.position.x, state.pose.position.y = -1.1, -1.1        # into the pillar: refused
    assert not fresh.call(SetEntityState, '/set_entity_state', state=state).success


def test_two_robots_in_namespaces_do_not_see_each_others_topics(fresh: Harness) -> None:
    from interfaces.gazebo_msgs.srv import DeleteEntity, GetModelList, SpawnEntity
    from interfaces.nav_msgs.msg import Odometry
    from interfaces.sensor_msgs.msg import LaserScan
    from interfaces.tf2_msgs.msg import TFMessage
    request = SpawnEntity.Request(name='tb3_1', robot_namespace='tb3_1', xml='<robot name="burger"/>')
    request.initial_pose.position.x, request.initial_pose.position.y = -1.5, -0.5
    response = fresh.call(SpawnEntity, '/spawn_entity', name=request.name, robot_namespace=request.robot_namespace,
                          xml=request.xml, initial_pose=request.initial_pose)
    assert response.success, response.status_message
    try:
        assert fresh.call(GetModelList, '/get_model_list').model_names == ['burger', 'tb3_1']
        mine, theirs = fresh.record(Odometry, '/odom'), fresh.record(Odometry, '/tb3_1/odom')
        scans = fresh.record(LaserScan, '/tb3_1/scan')
        fresh.twist(-0.2, topic='/tb3_1/cmd_vel')     # backs towards the first robot (0.5 m behind)
        fresh.step(1.0)
        fresh.wait('/tb3_1/odom', lambda m: m and m[-1].pose.pose.position.x < -1.6, what='tb3_1 to move')
        assert all(m.pose.pose.position.x == SPAWN[0] for m in mine)        # the first robot never moved
        assert theirs[-1].header.frame_id == 'odom' and theirs[-1].child_frame_id == 'base_footprint'
        # Gazebo publishes no fixed frames (robot_state_publisher's job): only what the plugins say.
        assert fresh.node.count_publishers('/tb3_1/tf_static') == 0
        fresh.record(TFMessage, '/tb3_1/tf')
        fresh.step(0.1)
        tf = fresh.wait('/tb3_1/tf', lambda m: m and m[-1], what="tb3_1's odom transform")
        assert [(t.header.frame_id, t.child_frame_id) for t in tf.transforms] == [('odom', 'base_footprint')]
        assert fresh.state('burger')[:2] == SPAWN
        # tb3_1's lidar sees the first robot's lidar housing straight behind it.
        last = fresh.wait('/tb3_1/scan', lambda m: m and m[-1].header.stamp.sec == 1 and m[-1],
                          what="tb3_1's scan at 1 s")      # the one taken where the robot stopped
        behind = np.asarray(last.ranges)[180]
        x1 = fresh.state('tb3_1')[0]
        gap = (x1 - 0.032 * 1) - (SPAWN[0] - 0.032) - BURGER.lidar_housing_radius
        assert behind == pytest.approx(gap, abs=0.05)
    finally:
        assert fresh.call(DeleteEntity, '/delete_entity', name='tb3_1').success
    wait_until(lambda: fresh.node.count_publishers('/tb3_1/scan') == 0, 10, message='tb3_1 topics to go')


def test_reset_world_get_map_and_run_to_time(fresh: Harness) -> None:
    from interfaces.nav_msgs.srv import GetMap
    from interfaces.ros_gz_interfaces.srv import ControlWorld
    from interfaces.rosgraph_msgs.msg import Clock
    from interfaces.std_srvs.srv import Empty
    grid = fresh.call(GetMap, '/sim/get_map').map
    data = np.asarray(grid.data).reshape(grid.info.height, grid.info.width)
    assert grid.info.resolution == pytest.approx(0.05) and set(np.unique(data)) == {0, 100}
    row = int((0.0 - grid.info.origin.position.y) / 0.05)
    col = int((0.0 - grid.info.origin.position.x) / 0.05)
    assert data[row, col] == 100            # the middle pillar
    clocks = fresh.record(Clock, '/clock')
    fresh.twist(0.2, 0.5)
    control = ControlWorld.Request().world_control
    control.run_to_sim_time.sec = 2
    assert fresh.call(ControlWorld, f'/world/{WORLD}/control', world_control=control).success
    fresh.wait('/clock', lambda m: m and m[-1].clock.sec == 2, what='/clock to reach 2 s')
    time.sleep(0.3)
    assert clocks[-1].clock.sec == 2 and clocks[-1].clock.nanosec == 0        # paused again there
    assert fresh.state()[0] > SPAWN[0] + 0.1
    fresh.call(Empty, '/reset_world')            # poses back, time goes on
    assert fresh.state()[:3] == (*SPAWN, 0.0)
    fresh.step(0.1)
    assert clocks[-1].clock.sec == 2


def test_seed_003s_gazebo_calls_work_as_printed(fresh: Harness, zros_cli: Any) -> None:
    """`/get_model_state` (ROS 1's GetModelState) and `/set_entity_state` with the course's name
    `turtlebot3_burger` for the robot TurtleBot3's launch spawns as `burger`."""
    from interfaces.gazebo_msgs.srv import GetModelState, SetModelState
    result = zros_cli('service', 'call', '/get_model_state', 'gazebo_msgs/GetModelState',
                      '{model_name: turtlebot3_burger}', timeout=30)
    assert result.returncode == 0 and 'success=True' in result.stdout, result
    assert 'position=geometry_msgs.msg.Point(x=-2.0, y=-0.5' in result.stdout, result
    result = zros_cli('service', 'call', '/set_entity_state', 'gazebo_msgs/SetEntityState',
                      '{state: {name: turtlebot3_burger, pose: {position: {x: 2.0, y: 1.0}}}}', timeout=30)
    assert result.returncode == 0 and 'success=True' in result.stdout, result
    assert fresh.state()[:2] == (2.0, 1.0)
    response = fresh.call(GetModelState, '/get_model_state', model_name='turtlebot3_waffle')
    assert not response.success and response.status_message == "GetModelState: model 'turtlebot3_waffle' does not exist"
    request = SetModelState.Request()
    request.model_state.model_name = 'burger'
    request.model_state.pose.position.x = 0.0      # the middle pillar
    response = fresh.call(SetModelState, '/set_model_state', model_state=request.model_state)
    assert not response.success and 'obstacle' in response.status_message
    assert fresh.state()[:2] == (2.0, 1.0)


def test_unpaused_the_clock_runs_faster_than_real_time(sim: Harness) -> None:
    from zros.parameter import Parameter
    from interfaces.rcl_interfaces.srv import SetParameters
    from interfaces.rosgraph_msgs.msg import Clock
    from interfaces.std_srvs.srv import Empty
    clocks = sim.record(Clock, '/clock')
    sim.call(SetParameters, '/gazebo/set_parameters',
             parameters=[Parameter('real_time_factor', value=20.0).to_parameter_msg()])
    sim.clear()
    start = time.monotonic()
    sim.call(Empty, '/unpause_physics')
    try:
        sim.wait('/clock', lambda m: len(m) > 10 and m[-1].clock.sec - m[0].clock.sec >= 4, 20,
                 what='4 s of simulated time')
        wall = time.monotonic() - start
    finally:
        sim.call(Empty, '/pause_physics')
        sim.call(SetParameters, '/gazebo/set_parameters',
                 parameters=[Parameter('real_time_factor', value=1.0).to_parameter_msg()])
    assert wall < 4.0          # faster than real time, however loaded the machine


def test_twist_stamped_drives_when_asked_for(spawn: Any) -> None:
    from interfaces.geometry_msgs.msg import TwistStamped
    from interfaces.nav_msgs.msg import Odometry
    harness, executor, ctx = _start_harness(spawn, 'world:=empty_world', 'enable_stamped_cmd_vel:=true',
                                            'real_time_factor:=0.0')
    try:
        harness.child.wait_for_output('cmd_vel as geometry_msgs/msg/TwistStamped', 30)
        truth = harness.record(Odometry, '/sim/ground_truth')
        msg = TwistStamped()
        msg.twist.linear.x = 0.2
        harness.publish(msg, '/cmd_vel')
        harness.wait('/sim/ground_truth', lambda m: m and m[-1].pose.pose.position.x > 0.5, 20,
                     what='the robot to drive 0.5 m')
    finally:
        executor.shutdown(timeout_sec=2)
        ctx.shutdown()


def test_encoder_odometry_starts_at_zero_where_the_robot_spawns(spawn: Any) -> None:
    from interfaces.nav_msgs.msg import Odometry
    harness, executor, ctx = _start_harness(spawn, 'world:=empty_world', 'odometry_source:=encoder',
                                            'x_pose:=1.0', 'y_pose:=2.0', 'real_time_factor:=0.0')
    try:
        harness.child.wait_for_output("Spawned burger 'burger' at x=1 y=2", 30)
        assert 'encoder odometry' in harness.child.output()
        odoms, truth = harness.record(Odometry, '/odom'), harness.record(Odometry, '/sim/ground_truth')
        harness.wait('/odom', lambda m: m, 20)
        first = odoms[0].pose.pose.position
        assert abs(first.x) < 1e-6 and abs(first.y) < 1e-6
        harness.wait('/sim/ground_truth', lambda m: m and m[-1].pose.pose.position.x == 1.0, 20)
    finally:
        executor.shutdown(timeout_sec=2)
        ctx.shutdown()


def test_bad_world_file_and_bad_spawn_are_one_line_errors(domain: int, tmp_path: Any, zros_cli: Any) -> None:
    bad = tmp_path / 'my_world.yaml'
    bad.write_text('name: mine\nobstacles:\n- circle: {center: [0, 0], radius: 0}\n')
    result = zros_cli('run', 'turtlebot3_gazebo', 'gzserver', '--ros-args', '-p', f'world:={bad}', timeout=30)
    assert_clean_failure(result, f'{bad}:3:', 'obstacles[0].circle.radius', 'must be > 0')
    result = zros_cli('run', 'turtlebot3_gazebo', 'gzserver', '--ros-args', '-p', 'world:=moon', timeout=30)
    assert_clean_failure(result, "unknown world 'moon'")
    result = zros_cli('run', 'turtlebot3_gazebo', 'gzserver', '--ros-args', '-p', 'world:=turtlebot3_world',
                      '-p', 'x_pose:=0.0', '-p', 'y_pose:=0.0', timeout=30)
    assert_clean_failure(result, 'cannot spawn the robot', 'obstacle')
    result = zros_cli('run', 'turtlebot3_gazebo', 'gzserver', '--ros-args', '-p', 'odometry_source:=gps', timeout=30)
    assert_clean_failure(result, "parameter 'odometry_source': odometry_source must be 'world' (1) or 'encoder' (0)")
