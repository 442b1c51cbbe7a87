"""gazebo_ros as real processes: gazebo.launch.py on an SDF world (with a model included from a
package's models/ folder), spawn_entity.py from a topic and from a file, the robot scanning the
world's walls, and the one-line errors of bad command lines."""
from __future__ import annotations

import sys
import threading
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from conftest import assert_clean_failure, wait_until

WALL = ('<model name="{name}"><static>1</static><pose>{pose}</pose><link name="l"><collision name="c">'
        '<geometry><box><size>6 0.2 1</size></box></geometry></collision></link></model>')
ROOM = ('<?xml version="1.0"?><sdf version="1.6"><world name="room">'
        '<include><uri>model://ground_plane</uri></include>'
        '<include><uri>model://north_wall</uri><pose>0 2.1 0.5 0 0 0</pose></include>'
        + WALL.format(name='south', pose='0 -2.1 0.5 0 0 0') + WALL.format(name='east', pose='3.1 0 0.5 0 0 1.5708')
        + WALL.format(name='west', pose='-3.1 0 0.5 0 0 1.5708') + '</world></sdf>')
ROBOT_SDF = ('<?xml version="1.0"?><sdf version="1.6"><model name="turtlebot3_burger">'
             '<link name="base_footprint"/></model></sdf>')


def write_room(tmp_path: Path) -> Path:
    """A 6 x 4 m room; its north wall is the model `north_wall` of a package on ZROS_NODE_PATH."""
    model = tmp_path / 'pkgs' / 'my_worlds' / 'models' / 'north_wall'
    model.mkdir(parents=True)
    (model / 'model.sdf').write_text('<sdf version="1.6">' + WALL.format(name='north_wall', pose='0 0 0 0 0 0') + '</sdf>')
    (tmp_path / 'pkgs' / 'my_worlds' / '__init__.py').write_text('')
    world = tmp_path / 'room.world'
    world.write_text(ROOM)
    return world


def test_spawn_entity_puts_a_robot_into_an_sdf_world_started_by_gazebo_launch(
        spawn: Any, context: Any, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    from zros.executors import MultiThreadedExecutor
    from zros.node import Node
    from zros.qos import DurabilityPolicy, QoSProfile
    from interfaces.gazebo_msgs.srv import GetEntityState
    from interfaces.sensor_msgs.msg import LaserScan
    from interfaces.std_msgs.msg import String
    world = write_room(tmp_path)
    monkeypatch.setenv('ZROS_NODE_PATH', str(tmp_path / 'pkgs'))
    monkeypatch.setenv('TURTLEBOT3_MODEL', 'burger')
    launch = spawn(sys.executable, '-m', 'zros', 'launch', 'gazebo_ros', 'gazebo.launch.py', f'world:={world}',
                   'gui:=false', name='launch')
    node = Node('gazebo_ros_test', context=context)
    description = node.create_publisher(String, 'robot_description',
                                        QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL))
    description.publish(String(data=ROBOT_SDF))
    scans: list[Any] = []
    node.create_subscription(LaserScan, 'scan', scans.append, 10)
    executor = MultiThreadedExecutor(context=context)
    executor.add_node(node)
    threading.Thread(target=executor.spin, daemon=True).start()
    try:
        spawner = spawn.run('gazebo_ros', 'spawn_entity.py', '-entity', 'my_robot', '-topic', 'robot_description',
                            '-x', '-1.0', '-y', '0.5', '-Y', '1.5707963')
        assert spawner.wait(60) == 0, f'{spawner.output()}\n{launch.output()}'
        assert 'Spawn status: SpawnEntity: Successfully spawned entity [my_robot]' in spawner.output()
        assert "model 'model://north_wall'" not in launch.output()      # found in my_worlds/models
        client = node.create_client(GetEntityState, '/get_entity_state')
        assert client.wait_for_service(timeout_sec=30), launch.output()
        state = client.call(GetEntityState.Request(name='my_robot'), timeout_sec=10)
        assert state.success and (state.state.pose.position.x, state.state.pose.position.y) == (-1.0, 0.5)
        wait_until(lambda: scans, 30, message=lambda: f'no /scan\n{launch.output()}')
        # Facing +y from (-1, 0.5), the lidar (0.032 m behind base_link's centre) sees the north
        # wall's face at y = 2.0 about 1.53 m ahead, and the west wall's at x = -3.0 on its left.
        ranges = np.asarray(scans[-1].ranges)
        assert ranges[0] == pytest.approx(2.0 - 0.5 + 0.032, abs=0.05)
        assert ranges[90] == pytest.approx(2.0, abs=0.05)
        # The same model from a file, into a namespace: a second robot.
        path = tmp_path / 'robot.sdf'
        path.write_text(ROBOT_SDF)
        second = spawn.run('gazebo_ros', 'spawn_entity.py', '-entity', 'second', '-file', str(path),
                           '-robot_namespace', 'tb3_1', '-x', '1.5', '-y', '-1.0')
        assert second.wait(60) == 0, second.output()
        assert f'Loading entity XML from file {path}' in second.output()
    finally:
        executor.shutdown(timeout_sec=2)


#: A student's launch file in ROBOTIS's shape: turtlebot3_gazebo's world file and model file by
#: path, Gazebo through gazebo_ros's gzserver.launch.py, the robot through spawn_entity.py.
STUDENT_GAZEBO_LAUNCH = '''
import os

from zros.ament_index_python.packages import get_package_share_directory
from zros.launch import LaunchDescription
from zros.launch.actions import IncludeLaunchDescription
from zros.launch.launch_description_sources import PythonLaunchDescriptionSource
from zros.launch_ros.actions import Node


def generate_launch_description():
    tb3 = get_package_share_directory('turtlebot3_gazebo')
    gazebo_ros = get_package_share_directory('gazebo_ros')
    world = os.path.join(tb3, 'worlds', 'turtlebot3_world.world')
    return LaunchDescription([
        IncludeLaunchDescription(PythonLaunchDescriptionSource(os.path.join(gazebo_ros, 'launch', 'gzserver.launch.py')),
                                 launch_arguments={'world': world}.items()),
        IncludeLaunchDescription(PythonLaunchDescriptionSource(
            os.path.join(tb3, 'launch', 'robot_state_publisher.launch.py')),
            launch_arguments={'use_sim_time': 'true'}.items()),
        Node(package='gazebo_ros', executable='spawn_entity.py', output='screen',
             arguments=['-entity', 'burger', '-file', os.path.join(tb3, 'models', 'turtlebot3_burger', 'model.sdf'),
                        '-x', '-2.0', '-y', '-0.5', '-z', '0.01']),
    ])
'''


def test_a_students_launch_file_with_turtlebot3_gazebos_world_and_model_files(
        spawn: Any, probe: Any, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """The robot publishes what its model.sdf says, odometry in the world frame (Gazebo's
    default): /odom starts at the spawn pose; the fixed frames and wheels come from
    robot_state_publisher alone."""
    from zros.tf2_ros import Buffer, TransformListener
    from zros.time import Time
    from interfaces.nav_msgs.msg import Odometry
    from interfaces.sensor_msgs.msg import JointState, LaserScan
    from interfaces.tf2_msgs.msg import TFMessage
    package = tmp_path / 'pkgs' / 'my_tb3'
    (package / 'launch').mkdir(parents=True)
    (package / 'launch' / 'world.launch.py').write_text(STUDENT_GAZEBO_LAUNCH)
    monkeypatch.setenv('ZROS_NODE_PATH', str(tmp_path / 'pkgs'))
    monkeypatch.setenv('TURTLEBOT3_MODEL', 'burger')
    launch = spawn(sys.executable, '-m', 'zros', 'launch', 'my_tb3', 'world.launch.py', name='launch')
    got: dict[str, list[Any]] = {'odom': [], 'scan': [], 'joint_states': [], 'tf': []}
    for msg_type, topic in ((Odometry, 'odom'), (LaserScan, 'scan'), (JointState, 'joint_states'), (TFMessage, 'tf')):
        probe.create_subscription(msg_type, topic, got[topic].append, 100)
    buffer = Buffer()
    TransformListener(buffer, probe)
    wait_until(lambda: all(got.values()), 60, message=lambda: f'odom, scan, joint_states, tf\n{launch.output()}')
    assert "Spawned burger 'burger' at x=-2 y=-0.5" in launch.output() and 'world odometry' in launch.output()
    first = got['odom'][0].pose.pose.position
    assert (first.x, first.y) == pytest.approx((-2.0, -0.5), abs=1e-6)
    assert got['scan'][-1].header.frame_id == 'base_scan' and len(got['scan'][-1].ranges) == 360
    assert list(got['joint_states'][-1].name) == ['wheel_left_joint', 'wheel_right_joint']
    wait_until(lambda: buffer.can_transform('odom', 'base_scan', Time()), 20,
               message=lambda: f'odom -> base_scan: {buffer.all_frames_as_string()}\n{launch.output()}')
    t = buffer.lookup_transform('odom', 'base_scan', Time()).transform.translation
    assert (t.x, t.y) == pytest.approx((-2.0 - 0.032, -0.5), abs=1e-6)
    # One broadcaster per frame: the simulator sends odom -> base_footprint, robot_state_publisher the rest.
    odom_messages = [m for m in list(got['tf']) if m.transforms[0].header.frame_id == 'odom']
    assert odom_messages and all(len(m.transforms) == 1 for m in odom_messages)
    assert probe.count_publishers('/tf_static') == 1


def test_bad_command_lines_are_one_line_errors(domain: int, tmp_path: Path, zros_cli: Any) -> None:
    result = zros_cli('run', 'gazebo_ros', 'spawn_entity.py', '-file', 'robot.sdf', timeout=30)
    assert_clean_failure(result, 'spawn_entity.py: the following arguments are required: -entity')
    result = zros_cli('run', 'gazebo_ros', 'spawn_entity.py', '-entity', 'r', '-file', str(tmp_path / 'none.sdf'),
                      timeout=30)
    assert_clean_failure(result, f'cannot read entity XML from {tmp_path / "none.sdf"}')
    bad = tmp_path / 'bad.world'
    bad.write_text('<sdf version="1.6"><world name="w">\n<model name="m"><pose>1 2</pose></model></world></sdf>')
    result = zros_cli('run', 'gazebo_ros', 'gzserver', str(bad), timeout=30)
    assert_clean_failure(result, f"{bad}:2: <pose> needs 6 finite numbers, got '1 2'")
    result = zros_cli('run', 'gazebo_ros', 'gzserver', '--physics', timeout=30)
    assert_clean_failure(result, 'gzserver: argument --physics: expected one argument')
