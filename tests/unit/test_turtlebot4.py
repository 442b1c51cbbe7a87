"""The TurtleBot4 half of Nav2 Jazzy's bringup: nav2_minimal_tb4_description's xacro, the
simulator's TurtleBot4, nav2_minimal_tb4_sim's files, and the depot and warehouse maps.

Nav2's tb4_simulation_launch.py feeds `xacro turtlebot4.urdf.xacro` to robot_state_publisher and
spawns the same description into Gazebo Sim; these tests read zros's files the way those two do.
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from zros.ament_index_python.packages import get_package_share_directory
from zros.launch import resolve
from zros.map_io import load_map
from zros.sim import Simulation, World, load_world
from zros.sim.gz_bridge import parse_bridge_config
from zros.sim.model_file import robot_from_xml
from zros.sim.robot import TURTLEBOT4
from zros.sim.sensors import RPLIDAR_A1
from zros.sim.world import box_loop
from zros.urdf import parse_urdf
from zros.urdf.xacro import process_file

from tools import world_maps


@pytest.fixture(scope='module')
def description() -> str:
    share = Path(get_package_share_directory('nav2_minimal_tb4_description'))
    return process_file(share / 'urdf' / 'standard' / 'turtlebot4.urdf.xacro')


def test_the_xacro_expands_to_the_frames_nav2_uses(description: str) -> None:
    robot = parse_urdf(description)
    assert {'base_link', 'base_footprint', 'shell_link', 'rplidar_link', 'left_wheel', 'right_wheel',
            'imu_link'} <= set(robot.links)
    assert robot.root == 'base_link'
    lidar = robot.joints['rplidar_joint']
    assert lidar.parent == 'shell_link' and lidar.origin.rpy[2] == pytest.approx(math.pi / 2)
    # the simulator's mount points are the description's
    poses = robot.link_poses()
    assert poses['rplidar_link'][:3] == pytest.approx(TURTLEBOT4.lidar_mount, abs=1e-3)
    assert poses['imu_link'][:3] == pytest.approx(TURTLEBOT4.imu_mount, abs=1e-3)
    assert poses['left_wheel'][:3] == pytest.approx(TURTLEBOT4.wheel_mounts[0], abs=1e-3)


def test_the_model_reads_as_a_turtlebot4_by_its_wheels(description: str) -> None:
    model = robot_from_xml(description, fallback='waffle')
    assert model.warning == '' and model.spec.model == 'turtlebot4'
    assert (model.spec.wheel_separation, model.spec.wheel_radius) == (0.233, 0.03575)
    assert (model.spec.max_linear, model.spec.max_angular, model.spec.max_wheel_acceleration) == (0.5, 2.0, 2.0)
    assert model.spec.body_radius == 0.164 and model.spec.lidar_yaw == pytest.approx(math.pi / 2)
    lidar = model.lidar
    assert (lidar.samples, lidar.angle_max, lidar.range_min, lidar.range_max, lidar.rate) == \
        (RPLIDAR_A1.samples, RPLIDAR_A1.angle_max, 0.164, 20.0, 10.0)
    topics = model.topics
    assert (topics.cmd_vel, topics.odom, topics.tf, topics.scan) == ('/cmd_vel', '/odom', '/tf', '/scan')
    assert (topics.odom_frame, topics.base_frame, topics.scan_frame) == ('odom', 'base_link', 'rplidar_link')


def test_other_wheels_keep_the_turtlebot3_the_model_names(description: str) -> None:
    other = description.replace('<wheel_separation>0.233<', '<wheel_separation>0.287<')
    assert robot_from_xml(other, fallback='waffle').spec.model == 'waffle'


def test_the_lidar_looks_along_its_own_frame() -> None:
    """rplidar_link is turned +90 degrees: its beam at -90 degrees looks straight ahead."""
    wall = World(name='wall', polygons=(tuple([box_loop(2.0, 0.0, 0.2, 10.0)]),))
    sim = Simulation(wall, seed=0)
    robot = sim.add_robot('tb4', (0.0, 0.0, 0.0), spec=TURTLEBOT4, lidar=RPLIDAR_A1)
    ranges = robot.scan(noise=False)
    ahead = int(round((1.5 * math.pi - RPLIDAR_A1.angle_min) / RPLIDAR_A1.angle_increment))
    assert ranges[ahead] == pytest.approx(1.9 - TURTLEBOT4.lidar_mount[0], abs=0.02)
    assert math.isinf(ranges[0])      # the beam along base_link's +y meets nothing


def test_the_bridge_config_carries_the_robots_topics() -> None:
    share = Path(get_package_share_directory('nav2_minimal_tb4_sim'))
    entries = parse_bridge_config((share / 'configs' / 'tb4_bridge.yaml').read_text(), 'tb4_bridge.yaml')
    pairs = {(e.ros_topic, e.gz_topic) for e in entries}
    assert {('scan', '/scan'), ('odom', '/odom'), ('cmd_vel', '/cmd_vel'), ('tf', '/tf'), ('/clock', '/clock')} <= pairs


def test_spawn_tb4_has_upstreams_arguments(tmp_path: Path) -> None:
    launch = Path(get_package_share_directory('nav2_minimal_tb4_sim')) / 'launch' / 'spawn_tb4.launch.py'
    plan = resolve(str(launch), launch_arguments={'robot_name': 'tb', 'x_pose': '1.5'}, log_dir=str(tmp_path))
    text = plan.describe()
    assert 'parameter_bridge' in text and '-topic robot_description' in text and '-name tb' in text
    assert '-x 1.5' in text
    without = resolve(str(launch), launch_arguments={'use_simulator': 'False'}, log_dir=str(tmp_path))
    assert '-topic robot_description' not in without.describe() and 'parameter_bridge' in without.describe()


@pytest.mark.parametrize('name, start', [('depot', (-8.0, 0.0, 0.0)), ('warehouse', (2.12, -21.3, 1.57))])
def test_the_worlds_load_and_the_robot_fits_at_upstreams_spawn(name: str, start: tuple, tmp_path: Path) -> None:
    share = Path(get_package_share_directory('nav2_minimal_tb4_sim'))
    warnings: list[str] = []
    expanded = tmp_path / f'{name}.sdf'
    expanded.write_text(process_file(share / 'worlds' / f'{name}.sdf', {'headless': 'False'}))
    world = load_world(expanded, on_warning=warnings.append)
    assert warnings == [] and world.name == name and len(world.polygons) > 20
    Simulation(world, seed=0).add_robot('tb4', start, spec=TURTLEBOT4, lidar=RPLIDAR_A1)


@pytest.mark.parametrize('name', ['depot', 'warehouse'])
def test_the_shipped_maps_are_the_worlds(name: str) -> None:
    """nav2_bringup's depot and warehouse maps are tools/world_maps.py's rasters of the worlds,
    on upstream's grids; the robot's spawn point is free on them."""
    spec = world_maps.MAPS[name]
    shipped = load_map(Path(get_package_share_directory('nav2_bringup')) / 'maps' / f'{name}.yaml')
    assert shipped.data.shape == spec.size and shipped.resolution == pytest.approx(spec.resolution)
    assert tuple(shipped.origin[:2]) == pytest.approx(spec.origin)
    assert np.array_equal(shipped.data, world_maps.world_map(spec).data)
    x, y = spec.spawn[0] - spec.frame[0], spec.spawn[1] - spec.frame[1]     # in the map's frame
    rows, cols = shipped.geometry.world_to_cell(np.array([x]), np.array([y]))
    assert shipped.data[rows[0], cols[0]] == 0
    assert (shipped.data == 100).mean() > 0.02
