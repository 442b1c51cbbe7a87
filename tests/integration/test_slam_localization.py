"""slam_toolbox's save-and-localize loop as real processes next to the simulator: the SLAM node
maps turtlebot3_world while the robot turns on the spot, serialize_map writes the pose graph, and
localization_slam_toolbox_node (started by slam_toolbox's localization_launch.py with
`map_file_name` and `map_start_pose`) finds the robot, teleported elsewhere so that its odometry
knows nothing of the move, to within a few centimetres of the simulator's truth. /initialpose
then relocalizes it after a second teleport. merge_maps_kinematic merges the saved graph."""
from __future__ import annotations

import math
import signal
import sys
import threading

import numpy as np

from conftest import wait_until

SPAWN = (-2.0, -0.5, 0.0)          # turtlebot3_world's spawn pose: the saved map's frame in the world
START = (-1.55, -0.55, 0.9)        # where localization starts (world), among the pillars' first row
MOVED = (-1.75, -0.2, -0.6)        # the second teleport, for /initialpose


def _pose_of(transform):
    from zros.rotations import yaw_from_quaternion
    t, r = transform.transform, transform.transform.rotation
    return np.array([t.translation.x, t.translation.y, yaw_from_quaternion(r.x, r.y, r.z, r.w)])


def test_save_the_pose_graph_then_localize_in_it_elsewhere(spawn, make_context, tmp_path):
    from zros.executors import MultiThreadedExecutor
    from zros.node import Node
    from zros.qos import DurabilityPolicy, QoSProfile
    from zros.rotations import quaternion_from_yaw, yaw_from_quaternion, wrap_angle
    from zros.slam.geometry import relative
    from zros.tf2_ros import Buffer, TransformException, TransformListener
    from zros.time import Time
    from interfaces.gazebo_msgs.srv import GetEntityState, SetEntityState
    from interfaces.geometry_msgs.msg import PoseWithCovarianceStamped, Twist
    from interfaces.nav_msgs.msg import OccupancyGrid
    from interfaces.slam_toolbox.srv import AddSubmap, MergeMaps, SerializePoseGraph

    sim = spawn.node('turtlebot3_gazebo', 'gzserver', '--ros-args', '-p', 'world:=turtlebot3_world',
                     '-p', 'real_time_factor:=2.0')
    slam = spawn.command(sys.executable, '-m', 'zros', 'run', 'slam_toolbox', 'async_slam_toolbox_node',
                         '--ros-args', '-p', 'use_sim_time:=true', name='slam')
    node = Node('probe', context=make_context())
    executor = MultiThreadedExecutor(context=node.context)
    executor.add_node(node)
    threading.Thread(target=executor.spin, daemon=True).start()
    buffer = Buffer()
    TransformListener(buffer, node)
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

    def robot_in_map():
        try:
            return _pose_of(buffer.lookup_transform('map', 'base_footprint', Time()))
        except TransformException:
            return None

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

    # 4. merge_maps_kinematic: the saved graph as a submap, then merged onto /map.
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
