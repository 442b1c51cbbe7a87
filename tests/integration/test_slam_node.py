"""The SLAM node as a real process next to the simulator: slam_toolbox's launch file starts it,
it maps what the lidar sees (checked against the world's exact occupancy), its map -> odom
transform absorbs an odometry error injected by teleporting the robot, its services save the map
and the pose graph, and Ctrl-C stops it cleanly. Humble's launch shape (a plain Node) and
Jazzy's (a LifecycleNode configured and activated by launch events) both leave it active, as
BasicNavigator.waitUntilNav2Active(localizer='slam_toolbox') expects.

And slam_toolbox's save-and-localize loop: the SLAM node maps turtlebot3_world while the robot
turns on the spot, serialize_map writes the pose graph, and localization_slam_toolbox_node
(started by slam_toolbox's localization_launch.py with `map_file_name` and `map_start_pose`)
finds the robot, teleported elsewhere so that its odometry knows nothing of the move, to within a
few centimetres of the simulator's truth; /initialpose relocalizes it after a second teleport;
lifelong_slam_toolbox_node maps on in the graph; merge_maps_kinematic merges it."""
from __future__ import annotations

import math
import signal
import sys
import threading

import numpy as np

from conftest import assert_clean_failure, wait_until

SPAWN = (-2.0, -0.5, 0.0)          # turtlebot3_world's spawn pose: with encoder odometry, the map frame's place
START = (-1.55, -0.55, 0.9)        # where localization starts (world), among the pillars' first row
MOVED = (-1.75, -0.2, -0.6)        # the second teleport, for /initialpose

#: slam_toolbox's online_async_launch.py of the ros2 (Jazzy) branch, in shape.
JAZZY_SLAM_LAUNCH = '''
from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument, EmitEvent, LogInfo, RegisterEventHandler
from launch.events import matches_action
from launch.substitutions import LaunchConfiguration
from launch_ros.actions import LifecycleNode
from launch_ros.event_handlers import OnStateTransition
from launch_ros.events.lifecycle import ChangeState
from lifecycle_msgs.msg import Transition


def generate_launch_description():
    slam = LifecycleNode(package='slam_toolbox', executable='async_slam_toolbox_node', name='slam_toolbox',
                         namespace='', output='screen',
                         parameters=[LaunchConfiguration('slam_params_file'),
                                     {'use_lifecycle_manager': False, 'use_sim_time': True}])
    return LaunchDescription([
        DeclareLaunchArgument('slam_params_file'),
        slam,
        EmitEvent(event=ChangeState(lifecycle_node_matcher=matches_action(slam),
                                    transition_id=Transition.TRANSITION_CONFIGURE)),
        RegisterEventHandler(OnStateTransition(
            target_lifecycle_node=slam, start_state='configuring', goal_state='inactive',
            entities=[LogInfo(msg='slam_toolbox is activating'),
                      EmitEvent(event=ChangeState(lifecycle_node_matcher=matches_action(slam),
                                                  transition_id=Transition.TRANSITION_ACTIVATE))])),
    ])
'''

#: A Nav2 mission's first step with SLAM instead of AMCL.
WAIT_FOR_SLAM = '''
import zros
from zros.nav2_simple_commander.robot_navigator import BasicNavigator

zros.init()
navigator = BasicNavigator()
print('NAV2 ACTIVE', navigator.waitUntilNav2Active(navigator='slam_toolbox', localizer='slam_toolbox', timeout=60))
zros.shutdown()
'''


def _pose_of(transform):
    from zros.rotations import yaw_from_quaternion
    t, r = transform.transform, transform.transform.rotation
    return np.array([t.translation.x, t.translation.y, yaw_from_quaternion(r.x, r.y, r.z, r.w)])


def _world(spawn):
    """turtlebot3_world's simulator, at twice real time, with encoder odometry (from (0, 0) at the
    spawn pose): a teleport is then an odometry error, for SLAM and localization to correct."""
    return spawn.node('turtlebot3_gazebo', 'gzserver', '--ros-args', '-p', 'world:=turtlebot3_world',
                      '-p', 'real_time_factor:=2.0', '-p', 'odometry_source:=encoder')


def _probe(make_context):
    """A probe node spinning in the background with a TF buffer: (node, executor, robot_in_map),
    robot_in_map() the latest map -> base_footprint as (x, y, yaw), or None."""
    from zros.executors import MultiThreadedExecutor
    from zros.node import Node
    from zros.tf2_ros import Buffer, TransformException, TransformListener
    from zros.time import Time
    node = Node('probe', context=make_context())
    executor = MultiThreadedExecutor(context=node.context)
    executor.add_node(node)
    threading.Thread(target=executor.spin, daemon=True).start()
    buffer = Buffer()
    TransformListener(buffer, node)

    def robot_in_map():
        try:
            return _pose_of(buffer.lookup_transform('map', 'base_footprint', Time()))
        except TransformException:
            return None
    return node, executor, robot_in_map, buffer


def test_slam_node_maps_the_world_and_corrects_an_odometry_error(spawn, make_context, zros_cli, tmp_path):
    from scipy import ndimage
    from zros.map_io import map_from_msg, load_map
    from zros.qos import DurabilityPolicy, QoSProfile
    from zros.slam.geometry import compose, relative
    from zros.time import Time
    from interfaces.gazebo_msgs.srv import SetEntityState
    from interfaces.nav_msgs.msg import OccupancyGrid
    from interfaces.nav_msgs.srv import GetMap
    from interfaces.slam_toolbox.srv import Pause, SaveMap, SerializePoseGraph

    params = tmp_path / 'slam.yaml'
    params.write_text('slam_toolbox:\n  ros__parameters:\n    map_update_interval: 0.5\n')
    sim = _world(spawn)
    slam = spawn.command(sys.executable, '-m', 'zros', 'launch', 'slam_toolbox', 'online_async_launch.py',
                         f'slam_params_file:={params}', 'use_sim_time:=true', name='slam_launch')
    node, executor, robot_in_map, buffer = _probe(make_context)
    maps = []
    node.create_subscription(OccupancyGrid, 'map', maps.append,
                             QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL))
    wait_until(lambda: maps, 60, message=f'/map from the SLAM node\n{slam.output()}\n{sim.output()}')
    wait_until(lambda: robot_in_map() is not None, 20, message='TF map -> odom -> base_footprint')
    assert np.allclose(robot_in_map(), 0.0, atol=0.02)

    # Teleport the robot: its odometry does not see the move, SLAM must (through map -> odom).
    moved = (SPAWN[0] + 0.10, SPAWN[1] + 0.07, 0.08)
    teleport = node.create_client(SetEntityState, '/set_entity_state')
    assert teleport.wait_for_service(timeout_sec=10)
    request = SetEntityState.Request()
    request.state.name = 'burger'
    request.state.pose.position.x, request.state.pose.position.y = moved[0], moved[1]
    request.state.pose.orientation.z, request.state.pose.orientation.w = math.sin(0.04), math.cos(0.04)
    assert teleport.call(request, timeout_sec=10).success
    expected = relative(np.array(SPAWN), np.array(moved))

    def corrected():
        pose = robot_in_map()
        return pose is not None and np.hypot(*(pose[:2] - expected[:2])) < 0.02 and abs(pose[2] - expected[2]) < 0.02
    wait_until(corrected, 20, message=f'map -> base_footprint {robot_in_map()} to reach {expected}')
    odom = _pose_of(buffer.lookup_transform('odom', 'base_footprint', Time()))
    assert np.hypot(*odom[:2]) < 0.02                       # odometry still thinks it has not moved

    # The map's walls are where the world's are (within one cell).
    truth_client = node.create_client(GetMap, '/sim/get_map')
    truth = map_from_msg(truth_client.call(GetMap.Request(), timeout_sec=10).map)
    near = ndimage.binary_dilation(truth.data == 100, structure=np.ones((3, 3), dtype=bool))
    grid = map_from_msg(maps[-1])
    rows, cols = np.nonzero(grid.data == 100)
    local = np.column_stack([grid.origin[0] + (cols + 0.5) * grid.resolution,
                             grid.origin[1] + (rows + 0.5) * grid.resolution, np.zeros(len(rows))])
    world = compose(np.array(SPAWN), local)[:, :2]
    cells = np.floor((world - truth.origin[:2]) / truth.resolution).astype(int)
    assert len(cells) > 100 and near[cells[:, 1], cells[:, 0]].mean() > 0.95

    # slam_toolbox's services.
    save = node.create_client(SaveMap, 'slam_toolbox/save_map')
    assert save.wait_for_service(timeout_sec=10)
    request = SaveMap.Request()
    request.name.data = str(tmp_path / 'saved')
    assert save.call(request, timeout_sec=10).result == SaveMap.Response.RESULT_SUCCESS
    assert (load_map(tmp_path / 'saved.yaml').data == 100).sum() > 100
    serialize = node.create_client(SerializePoseGraph, 'slam_toolbox/serialize_map')
    assert serialize.wait_for_service(timeout_sec=10)
    result = serialize.call(SerializePoseGraph.Request(filename=str(tmp_path / 'graph')), timeout_sec=10)
    assert result.result == 0 and (tmp_path / 'graph.posegraph').stat().st_size > 1000
    _assert_active_for_nav2(spawn, zros_cli)     # Humble's launch shape: the node started itself
    pause = node.create_client(Pause, 'slam_toolbox/pause_new_measurements')
    assert pause.wait_for_service(timeout_sec=10) and pause.call(Pause.Request(), timeout_sec=10).status
    slam.wait_for_output('Processing of new measurements paused', timeout=5)

    executor.shutdown(timeout_sec=1)
    slam.signal(signal.SIGINT)
    assert slam.wait(5) == 0, slam.output()


def _assert_active_for_nav2(spawn, zros_cli) -> None:
    assert zros_cli('lifecycle', 'get', '/slam_toolbox', timeout=30).stdout.strip() == 'active [3]'
    waiting = spawn.script(WAIT_FOR_SLAM, name='navigator')
    assert 'NAV2 ACTIVE True' in waiting.wait_for_output('NAV2 ACTIVE', timeout=90), waiting.output()


def test_jazzy_launch_shape_configures_and_activates_the_lifecycle_node(spawn, make_context, zros_cli, tmp_path):
    from zros.executors import SingleThreadedExecutor
    from zros.node import Node
    from zros.qos import DurabilityPolicy, QoSProfile
    from interfaces.nav_msgs.msg import OccupancyGrid

    params = tmp_path / 'slam.yaml'
    params.write_text('slam_toolbox:\n  ros__parameters:\n    map_update_interval: 0.5\n')
    launch_file = tmp_path / 'online_async_launch.py'
    launch_file.write_text(JAZZY_SLAM_LAUNCH)
    printed = zros_cli('launch', str(launch_file), f'slam_params_file:={params}', '--print', timeout=30)
    for line in ('change state of [async_slam_toolbox_node-1]: configure [1]',
                 'on state transition configuring -> inactive of [async_slam_toolbox_node-1]:',
                 '  change state of [async_slam_toolbox_node-1]: activate [3]'):
        assert line in printed.stdout.splitlines(), printed
    sim = _world(spawn)
    slam = spawn.command(sys.executable, '-m', 'zros', 'launch', str(launch_file), f'slam_params_file:={params}',
                         name='slam_launch')
    slam.wait_for_output('Waiting unconfigured for its lifecycle transitions', timeout=60)
    slam.wait_for_output("lifecycle transition 'activate' of /slam_toolbox done: now active", timeout=90)
    assert slam.output().index('slam_toolbox is activating') < slam.output().index('now active')

    node = Node('probe', context=make_context())
    executor = SingleThreadedExecutor(context=node.context)
    executor.add_node(node)
    maps = []
    node.create_subscription(OccupancyGrid, 'map', maps.append,
                             QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL))
    wait_until(lambda: executor.spin_once(timeout_sec=0.2) or maps, 60,
               message=f'/map from the SLAM node\n{slam.output()}\n{sim.output()}')
    assert max(maps[-1].data) == 100
    _assert_active_for_nav2(spawn, zros_cli)
    slam.signal(signal.SIGINT)
    assert slam.wait(15) == 0, slam.output()


def test_slam_node_rejects_a_parameter_of_the_wrong_type(zros_cli, domain):
    result = zros_cli('run', 'slam_toolbox', 'async_slam_toolbox_node', '--ros-args', '-p', 'resolution:=fine',
                      timeout=30)
    assert_clean_failure(result, "'resolution'")
    result = zros_cli('run', 'slam_toolbox', 'async_slam_toolbox_node', '--ros-args', '-p', 'resolution:=-0.05',
                      timeout=30)
    assert_clean_failure(result, 'resolution must be > 0')


def test_save_the_pose_graph_then_localize_in_it_elsewhere(spawn, make_context, tmp_path):
    from zros.qos import DurabilityPolicy, QoSProfile
    from zros.rotations import quaternion_from_yaw, yaw_from_quaternion, wrap_angle
    from zros.slam.geometry import relative
    from zros.slam.serialization import read_pose_graph
    from interfaces.gazebo_msgs.srv import GetEntityState, SetEntityState
    from interfaces.geometry_msgs.msg import PoseWithCovarianceStamped, Twist
    from interfaces.nav_msgs.msg import OccupancyGrid
    from interfaces.slam_toolbox.srv import AddSubmap, MergeMaps, SerializePoseGraph

    sim = _world(spawn)
    slam = spawn.command(sys.executable, '-m', 'zros', 'run', 'slam_toolbox', 'async_slam_toolbox_node',
                         '--ros-args', '-p', 'use_sim_time:=true', name='slam')
    node, executor, robot_in_map, _ = _probe(make_context)
    cmd_vel = node.create_publisher(Twist, '/cmd_vel', 10)
    get_state = node.create_client(GetEntityState, '/get_entity_state')
    set_state = node.create_client(SetEntityState, '/set_entity_state')
    assert get_state.wait_for_service(timeout_sec=30), sim.output()

    def truth():
        state = get_state.call(GetEntityState.Request(name='burger'), timeout_sec=10).state.pose
        q = state.orientation
        return np.array([state.position.x, state.position.y, yaw_from_quaternion(q.x, q.y, q.z, q.w)])

    def teleport(pose):
        request = SetEntityState.Request()
        request.state.name = 'burger'
        request.state.pose.position.x, request.state.pose.position.y = pose[0], pose[1]
        q = request.state.pose.orientation
        q.x, q.y, q.z, q.w = quaternion_from_yaw(pose[2])
        assert set_state.call(request, timeout_sec=10).success

    def near(expected, xy=0.04, yaw=0.03):
        pose = robot_in_map()
        return (pose is not None and np.hypot(*(pose[:2] - expected[:2])) < xy
                and abs(wrap_angle(pose[2] - expected[2])) < yaw)

    # 1. Map: one turn on the spot at the spawn point sees most of the arena.
    wait_until(lambda: robot_in_map() is not None, 60, message=lambda: f'SLAM map -> odom\n{slam.output()}')
    turn, last = 0.0, truth()[2]
    twist = Twist()
    twist.angular.z = 0.8
    while turn < 2 * math.pi + 0.3:
        cmd_vel.publish(twist)
        wait_until(lambda: abs(wrap_angle(truth()[2] - last)) > 0.2, 10, message='the robot to turn')
        yaw = truth()[2]
        turn, last = turn + abs(wrap_angle(yaw - last)), yaw
    cmd_vel.publish(Twist())
    mapped = relative(np.array(SPAWN), truth())
    wait_until(lambda: near(mapped, 0.03, 0.03), 20, message=lambda: f'SLAM to follow the turn: {robot_in_map()}')
    serialize = node.create_client(SerializePoseGraph, 'slam_toolbox/serialize_map')
    assert serialize.wait_for_service(timeout_sec=10)
    graph = tmp_path / 'turtlebot3_world'
    assert serialize.call(SerializePoseGraph.Request(filename=str(graph)), timeout_sec=20).result == 0
    assert (tmp_path / 'turtlebot3_world.posegraph').is_file() and (tmp_path / 'turtlebot3_world.data').is_file()
    slam.signal(signal.SIGINT)
    assert slam.wait(10) == 0, slam.output()

    # 2. Localize: the robot is elsewhere, its odometry unaware; the start pose given is 8 cm off.
    teleport(START)
    expected = relative(np.array(SPAWN), truth())
    given = expected + np.array([0.06, -0.05, 0.06])
    params = tmp_path / 'localization.yaml'
    params.write_text('slam_toolbox:\n  ros__parameters:\n'
                      f'    map_file_name: {graph}\n'
                      f'    map_start_pose: [{given[0]:.4f}, {given[1]:.4f}, {given[2]:.4f}]\n')
    maps = []
    node.create_subscription(OccupancyGrid, 'map', maps.append,
                             QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL))
    localization = spawn.command(sys.executable, '-m', 'zros', 'launch', 'slam_toolbox', 'localization_launch.py',
                                 f'slam_params_file:={params}', name='localization')
    localization.wait_for_output('Pose graph loaded from', timeout=60)
    wait_until(lambda: near(expected), 30,
               message=lambda: f'map -> base_footprint {robot_in_map()} to reach {expected}\n{localization.output()}')
    wait_until(lambda: maps and max(maps[-1].data) == 100, 20, message='the loaded map on /map')

    # 3. /initialpose relocalizes after another move odometry does not see.
    teleport(MOVED)
    expected = relative(np.array(SPAWN), truth())
    initial = PoseWithCovarianceStamped()
    initial.header.frame_id = 'map'
    initial.pose.pose.position.x, initial.pose.pose.position.y = expected[0] - 0.05, expected[1] + 0.05
    q = initial.pose.pose.orientation
    q.x, q.y, q.z, q.w = quaternion_from_yaw(float(expected[2]) + 0.05)
    node.create_publisher(PoseWithCovarianceStamped, '/initialpose', 1).publish(initial)
    localization.wait_for_output('Localizing to', timeout=10)
    wait_until(lambda: near(expected), 30,
               message=lambda: f'map -> base_footprint {robot_in_map()} to reach {expected}\n{localization.output()}')
    localization.signal(signal.SIGINT)
    assert localization.wait(15) == 0, localization.output()

    # 4. Lifelong mapping: the graph loaded where the robot is, and mapping goes on in it.
    lifelong = spawn.command(sys.executable, '-m', 'zros', 'run', 'slam_toolbox', 'lifelong_slam_toolbox_node',
                             '--ros-args', '-p', 'use_sim_time:=true', '-p', f'map_file_name:={graph}',
                             '-p', f'map_start_pose:=[{expected[0]:.4f}, {expected[1]:.4f}, {expected[2]:.4f}]',
                             name='lifelong')
    lifelong.wait_for_output('mapping from', timeout=60)
    wait_until(lambda: near(expected), 30, message=lambda: f'lifelong: {robot_in_map()}\n{lifelong.output()}')
    grown = tmp_path / 'grown'

    def grew() -> bool:     # the old graph, and more (once the node has taken a scan: later on a busy machine)
        assert serialize.call(SerializePoseGraph.Request(filename=str(grown)), timeout_sec=20).result == 0
        return len(read_pose_graph(grown).poses) > len(read_pose_graph(graph).poses)
    wait_until(grew, 20, message=lambda: f'lifelong to add a node to the loaded graph\n{lifelong.output()}')
    lifelong.signal(signal.SIGINT)
    assert lifelong.wait(15) == 0, lifelong.output()

    # 5. merge_maps_kinematic: the saved graph as a submap, then merged onto /map.
    maps.clear()
    merge = spawn.command(sys.executable, '-m', 'zros', 'launch', 'slam_toolbox', 'merge_maps_kinematic_launch.py',
                          name='merge')
    add = node.create_client(AddSubmap, 'slam_toolbox/add_submap')
    assert add.wait_for_service(timeout_sec=30), merge.output()
    add.call(AddSubmap.Request(filename=str(graph)), timeout_sec=20)
    merge.wait_for_output('was loaded into /map_1', timeout=10)
    node.create_client(MergeMaps, 'slam_toolbox/merge_submaps').call(MergeMaps.Request(), timeout_sec=20)
    wait_until(lambda: maps and max(maps[-1].data) == 100, 20, message=lambda: f'the merged /map\n{merge.output()}')
    executor.shutdown(timeout_sec=1)
    merge.signal(signal.SIGINT)
    assert merge.wait(15) == 0, merge.output()
