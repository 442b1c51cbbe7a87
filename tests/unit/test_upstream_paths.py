"""The files courses and upstream launch files name inside zros's packages, by upstream's paths.

`os.path.join(get_package_share_directory('nav2_bringup'), 'params', 'nav2_params.yaml')` and its
like are how ROS 2 projects reach a package's data. Each (package, path) pair below is one such
reference (from Nav2's, TurtleBot3's and the courses' launch files); it is found through zros's
package index, as those launch files find it, and read with the reader zros itself uses for
that kind of file. Nothing is fetched: the files are zros's own.
"""
from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest

from zros.ament_index_python.packages import get_package_share_directory
from zros.launch import resolve
from zros.map_io import load_map
from zros.parameter import load_parameter_file
from zros.slam.cartographer_lua import read_options
from zros.urdf import load_urdf
from zros.view.scene.config import load_config

#: nav2_bringup's params file: every node of Nav2's bringup, Humble's and Jazzy's.
NAV2_NODES = ('/amcl', '/bt_navigator', '/controller_server', '/local_costmap/local_costmap',
              '/global_costmap/global_costmap', '/map_server', '/map_saver', '/planner_server', '/smoother_server',
              '/behavior_server', '/waypoint_follower', '/velocity_smoother', '/collision_monitor',
              '/route_server', '/docking_server', '/loopback_simulator')
TB3_NODES = ('/amcl', '/bt_navigator', '/controller_server', '/local_costmap/local_costmap',
             '/global_costmap/global_costmap', '/planner_server', '/behavior_server', '/waypoint_follower')

REFERENCES = [
    ('nav2_bringup', 'params/nav2_params.yaml', 'params'),
    ('nav2_bringup', 'maps/turtlebot3_world.yaml', 'map'),
    ('nav2_bringup', 'maps/tb3_sandbox.yaml', 'map'),
    ('nav2_bringup', 'urdf/turtlebot3_waffle.urdf', 'urdf'),
    ('nav2_bringup', 'rviz/nav2_default_view.rviz', 'rviz'),
    ('nav2_bringup', 'launch/bringup_launch.py', 'launch'),
    ('nav2_bringup', 'launch/navigation_launch.py', 'launch'),
    ('nav2_bringup', 'launch/localization_launch.py', 'launch'),
    ('nav2_bringup', 'launch/slam_launch.py', 'launch'),
    ('nav2_bringup', 'launch/rviz_launch.py', 'launch'),
    ('nav2_loopback_sim', 'loopback_simulation.launch.py', 'launch'),
    ('turtlebot3_navigation2', 'launch/navigation2.launch.py', 'launch'),
    ('turtlebot3_navigation2', 'map/map.yaml', 'map'),
    ('turtlebot3_navigation2', 'rviz/tb3_navigation2.rviz', 'rviz'),
    *[('turtlebot3_navigation2', f'param/{sub}{model}.yaml', 'tb3_params')
      for sub in ('', 'humble/') for model in ('burger', 'waffle', 'waffle_pi')],
    ('turtlebot3_cartographer', 'launch/cartographer.launch.py', 'launch'),
    ('turtlebot3_cartographer', 'launch/occupancy_grid.launch.py', 'launch'),
    ('turtlebot3_cartographer', 'config/turtlebot3_lds_2d.lua', 'lua'),
    ('turtlebot3_cartographer', 'rviz/tb3_cartographer.rviz', 'rviz'),
    ('turtlebot3_description', 'urdf/turtlebot3_burger.urdf', 'urdf'),
]


def _check_params(path: Path, nodes: tuple[str, ...]) -> None:
    for node in nodes:
        assert load_parameter_file(str(path), node), f'{path}: no parameters for {node}'
    controller = load_parameter_file(str(path), '/controller_server')
    assert controller['controller_plugins'] == ['FollowPath'] and 'FollowPath.plugin' in controller


def _check_map(path: Path) -> None:
    grid = load_map(path)
    assert grid.data.shape[0] > 100 and grid.resolution == pytest.approx(0.05)
    # turtlebot3_world: free at the robot's spawn point, the middle pillar's outline occupied.
    rows, cols = grid.geometry.world_to_cell(np.array([-2.0]), np.array([-0.5]))
    assert grid.data[rows[0], cols[0]] == 0
    xs, ys = grid.geometry.centres()
    assert (grid.data[np.hypot(xs, ys) < 0.25] == 100).any()


@pytest.mark.parametrize('package, relative, kind', REFERENCES, ids=[f'{p}/{r}' for p, r, _ in REFERENCES])
def test_upstream_path_resolves_and_reads(package: str, relative: str, kind: str, tmp_path: Path) -> None:
    path = Path(get_package_share_directory(package)) / relative
    assert path.is_file(), f'{package}: {relative} is missing'
    if kind == 'params':
        _check_params(path, NAV2_NODES)
    elif kind == 'tb3_params':
        _check_params(path, TB3_NODES)
    elif kind == 'map':
        _check_map(path)
    elif kind == 'urdf':
        robot = load_urdf(path)
        assert {'base_footprint', 'base_link', 'base_scan'} <= set(robot.links)
    elif kind == 'rviz':
        assert load_config(path).fixed_frame == 'map'
    elif kind == 'lua':
        assert read_options(path)['map_frame'] == 'map'
    else:
        plan = resolve(str(path), log_dir=str(tmp_path))
        assert plan.processes_in_start_order(), f'{relative}: plans no process'


def test_the_nav2_maps_are_the_same_world_on_nav2s_grid() -> None:
    """Jazzy's tb3_sandbox is Humble's turtlebot3_world under a new name (Nav2 ships the same
    image twice): 384 x 384 cells from (-10, -10)."""
    share = Path(get_package_share_directory('nav2_bringup')) / 'maps'
    world, sandbox = load_map(share / 'turtlebot3_world.yaml'), load_map(share / 'tb3_sandbox.yaml')
    assert world.data.shape == (384, 384) and world.origin[:2] == (-10.0, -10.0)
    assert np.array_equal(world.data, sandbox.data)


def test_navigation2_reads_the_humble_params_under_ros_distro_humble(tmp_path: Path, monkeypatch) -> None:
    launch = Path(get_package_share_directory('turtlebot3_navigation2')) / 'launch' / 'navigation2.launch.py'
    monkeypatch.setenv('TURTLEBOT3_MODEL', 'waffle_pi')
    for distro, expected in (('humble', os.path.join('param', 'humble', 'waffle_pi.yaml')),
                             ('jazzy', os.path.join('param', 'waffle_pi.yaml'))):
        monkeypatch.setenv('ROS_DISTRO', distro)
        plan = resolve(str(launch), launch_arguments={'rviz': 'false'}, log_dir=str(tmp_path))
        assert expected in plan.describe()


def test_a_launch_file_beside_the_scripts_is_no_executable() -> None:
    """nav2_loopback_sim's launch file sits in the package folder, where ROS installs it."""
    from zros.ament_index_python.executables import executables
    assert executables('nav2_loopback_sim') == ['loopback_simulator']
