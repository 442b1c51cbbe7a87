"""The SLAM node as a real process next to the simulator: slam_toolbox's launch file starts it,
it maps what the lidar sees (checked against the world's exact occupancy), its map -> odom
transform absorbs an odometry error injected by teleporting the robot, its services save the map
and the pose graph, and Ctrl-C stops it cleanly. Humble's launch shape (a plain Node) and
Jazzy's (a LifecycleNode configured and activated by launch events) both leave it active, as
BasicNavigator.waitUntilNav2Active(localizer='slam_toolbox') expects."""
from __future__ import annotations

import math
import signal
import sys
import threading

import numpy as np

from conftest import assert_clean_failure, wait_until

SPAWN = (-2.0, -0.5, 0.0)          # turtlebot3_world's spawn pose: with encoder odometry, the map frame's place

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


def test_slam_node_maps_the_world_and_corrects_an_odometry_error(spawn, make_context, zros_cli, tmp_path):
    from scipy import ndimage
    from zros.executors import MultiThreadedExecutor
    from zros.map_io import map_from_msg, load_map
    from zros.node import Node
    from zros.qos import DurabilityPolicy, QoSProfile
    from zros.slam.geometry import compose, relative
    from zros.tf2_ros import Buffer, TransformException, TransformListener
    from zros.time import Time
    from interfaces.gazebo_msgs.srv import SetEntityState
    from interfaces.nav_msgs.msg import OccupancyGrid
    from interfaces.nav_msgs.srv import GetMap
    from interfaces.slam_toolbox.srv import Pause, SaveMap, SerializePoseGraph

    params = tmp_path / 'slam.yaml'
    params.write_text('slam_toolbox:\n  ros__parameters:\n    map_update_interval: 0.5\n')
    # Encoder odometry (from (0, 0) at the spawn pose): a teleport is then an odometry error.
    sim = spawn.node('turtlebot3_gazebo', 'gzserver', '--ros-args', '-p', 'world:=turtlebot3_world',
                     '-p', 'real_time_factor:=2.0', '-p', 'odometry_source:=encoder')
    slam = spawn.command(sys.executable, '-m', 'zros', 'launch', 'slam_toolbox', 'online_async_launch.py',
                         f'slam_params_file:={params}', 'use_sim_time:=true', name='slam_launch')

    node = Node('probe', context=make_context())
    executor = MultiThreadedExecutor(context=node.context)
    executor.add_node(node)
    threading.Thread(target=executor.spin, daemon=True).start()
    buffer = Buffer()
    TransformListener(buffer, node)
    maps = []
    node.create_subscription(OccupancyGrid, 'map', maps.append,
                             QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL))
    wait_until(lambda: maps, 60, message=f'/map from the SLAM node\n{slam.output()}\n{sim.output()}')

    def robot_in_map():
        try:
            return _pose_of(buffer.lookup_transform('map', 'base_footprint', Time()))
        except TransformException:
            return None
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
    # Encoder odometry (from (0, 0) at the spawn pose): a teleport is then an odometry error.
    sim = spawn.node('turtlebot3_gazebo', 'gzserver', '--ros-args', '-p', 'world:=turtlebot3_world',
                     '-p', 'real_time_factor:=2.0', '-p', 'odometry_source:=encoder')
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
