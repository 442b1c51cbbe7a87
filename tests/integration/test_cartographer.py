"""cartographer_ros's nodes by their ROS names, as turtlebot3_cartographer's launch files start
them (seed 000's `ros2 launch turtlebot3_cartographer cartographer.launch.py`): the Lua
configuration read without processes, then the two nodes mapping next to the simulator."""
from __future__ import annotations

import sys
import threading
from pathlib import Path

import numpy as np
import pytest

from conftest import REPO, assert_clean_failure, wait_until
from zros.map_io import OccupancyMap, resample
from zros.slam.cartographer_lua import LuaConfigError, read_options, slam_parameters

CONFIG = REPO / 'nodes' / 'turtlebot3_cartographer' / 'config'


def test_the_shipped_lua_configuration_reads_as_cartographer_would():
    options = read_options(CONFIG / 'turtlebot3_lds_2d.lua')
    assert options['tracking_frame'] == 'imu_link' and options['provide_odom_frame'] is False
    assert options['pose_publish_period_sec'] == 5e-3 and options['map_builder'] is None
    assert options['TRAJECTORY_BUILDER_2D.max_range'] == 3.5
    assert np.isclose(options['TRAJECTORY_BUILDER_2D.motion_filter.max_angle_radians'], np.radians(0.1))
    assert slam_parameters(options) == {'map_frame': 'map', 'odom_frame': 'odom', 'max_laser_range': 3.5,
                                        'missing_data_ray_length': 3.0, 'transform_timeout': 0.2}


def test_lua_includes_nesting_and_errors(tmp_path: Path):
    (tmp_path / 'base.lua').write_text('TRAJECTORY_BUILDER_2D = {}\nTRAJECTORY_BUILDER_2D.max_range = 8 -- metres\n')
    (tmp_path / 'robot.lua').write_text('include "base.lua"\ninclude "map_builder.lua"\n'
                                        'options = { map_frame = "world", nested = { a = -1, b = \'x\' }; }\n'
                                        'TRAJECTORY_BUILDER_2D.max_range = 12.\nreturn options\n')
    options = read_options(tmp_path / 'robot.lua')
    assert options['map_frame'] == 'world' and options['nested'] == {'a': -1, 'b': 'x'}
    assert options['TRAJECTORY_BUILDER_2D.max_range'] == 12.0          # the later assignment wins
    (tmp_path / 'bad.lua').write_text('options = {\n  map_frame = "map",\n  odom_frame = \n}\n')
    with pytest.raises(LuaConfigError, match=r'bad\.lua:4: unexpected'):
        read_options(tmp_path / 'bad.lua')
    with pytest.raises(LuaConfigError, match='cannot read'):
        read_options(tmp_path / 'missing.lua')


def test_resampling_keeps_thin_walls_and_the_origin():
    data = np.zeros((40, 40), np.int8)
    data[:, 21] = 100                       # a wall one cell thick
    data[:5, :] = -1
    grid = OccupancyMap(data, 0.05, (-1.0, -1.0, 0.0))
    coarse = resample(grid, 0.1)
    assert coarse.data.shape == (20, 20) and coarse.origin == grid.origin
    assert (coarse.data[3:, 10] == 100).all()         # the wall survives a coarser map
    fine = resample(grid, 0.025)
    assert fine.data.shape == (80, 80) and (fine.data[10:, 42:44] == 100).all() and (fine.data[:10, :40] == -1).all()
    assert resample(grid, 0.05) is grid


def test_bad_arguments_are_one_line(zros_cli, domain, tmp_path: Path):
    assert_clean_failure(zros_cli('run', 'cartographer_ros', 'cartographer_node', '-configuration_directory', tmp_path,
                                  '-configuration_basename', 'nope.lua'), 'cannot read')
    assert_clean_failure(zros_cli('run', 'cartographer_ros', 'cartographer_occupancy_grid_node', '-resolution', '0'),
                         'must be > 0')


def test_the_course_launch_maps_next_to_the_simulator(spawn, make_context):
    from zros.executors import ExternalShutdownException, SingleThreadedExecutor
    from zros.node import Node
    from zros.qos import DurabilityPolicy, QoSProfile
    from interfaces.nav_msgs.msg import OccupancyGrid
    sim = spawn.node('turtlebot3_gazebo', 'gzserver', '--ros-args', '-p', 'world:=turtlebot3_world')
    launch = spawn.command(sys.executable, '-m', 'zros', 'launch', 'turtlebot3_cartographer', 'cartographer.launch.py',
                           'use_sim_time:=True', 'use_rviz:=false', 'resolution:=0.1', name='cartographer')
    node = Node('probe', context=make_context())
    executor = SingleThreadedExecutor(context=node.context)
    executor.add_node(node)

    def spin() -> None:
        try:
            executor.spin()
        except ExternalShutdownException:
            pass   # the test's context went down first
    threading.Thread(target=spin, daemon=True).start()
    maps = []
    node.create_subscription(OccupancyGrid, 'map', maps.append,
                             QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL))
    wait_until(lambda: maps, 60, message=lambda: f'/map\n{launch.output()}\n{sim.output()}')
    assert all((np.asarray(m.data) != -1).any() for m in maps)        # nothing before a scan is in
    assert maps[-1].info.resolution == pytest.approx(0.1)
    wait_until(lambda: (np.asarray(maps[-1].data) == 100).sum() > 20, 30,
               message='the walls and pillars the lidar sees from the spawn pose')
    names = {name for name, _ in node.get_node_names_and_namespaces()}
    assert {'cartographer_node', 'cartographer_occupancy_grid_node'} <= names, names
