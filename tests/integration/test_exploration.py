"""explore_lite's role end to end with the real SLAM node: the simulator in a small world that is
unknown at the start, `zros launch nav2_bringup bringup_launch.py slam:=True` (slam_toolbox's
node and the navigation servers) and `zros launch explore_lite explore.launch.py`: exploration
ends by itself ("All frontiers traversed/tried out") with SLAM's map complete, then returns to
its start."""
from __future__ import annotations

import sys
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from conftest import background_node, wait_until
from zros.ament_index_python.packages import get_package_share_directory

WORLD = """
name: explore_room
spawn: {x: -1.0, y: -1.0, yaw: 0.0}
obstacles:
- ring: {center: [0, 0], sides: 4, inner_circumradius: 2.55, outer_circumradius: 2.83}
- box: {center: [0.0, -0.4], size: [0.3, 2.8], yaw: 0.0}
"""


@pytest.mark.timeout(300)   # a whole exploration: usually 45 s, several minutes on a loaded machine
def test_exploration_with_slam_maps_the_world_and_stops(spawn: Any, tmp_path: Any) -> None:
    from scipy import ndimage
    from zros.qos import DurabilityPolicy, QoSProfile
    from zros.sim import parse_world, rasterize
    from interfaces.nav_msgs.msg import OccupancyGrid
    world_file = tmp_path / 'explore_room.yaml'
    world_file.write_text(WORLD)
    world = parse_world(WORLD)
    spawn.node('turtlebot3_gazebo', 'gzserver', '--ros-args', '-p', f'world:={world_file}', '-p', 'real_time_factor:=5.0')
    burger = Path(get_package_share_directory('turtlebot3_navigation2')) / 'param' / 'burger.yaml'
    nav = spawn.command(sys.executable, '-m', 'zros', 'launch', 'nav2_bringup', 'bringup_launch.py',
                        'use_sim_time:=True', 'slam:=True', f'params_file:={burger}', name='navigation')
    # The free space inside the walls, by the exact raster, as cell centres in SLAM's map frame
    # (the frame the robot started in).
    truth = rasterize(world, 0.05)
    labels, _ = ndimage.label(~truth.cells)
    rows, cols = np.nonzero(labels == labels[truth.cell_of(world.spawn.x, world.spawn.y)])
    inside = np.stack([cols, rows], axis=1) * 0.05 + np.asarray(truth.origin) + 0.025 - (world.spawn.x, world.spawn.y)
    latest: dict[str, Any] = {}

    def share_known() -> float:
        msg = latest.get('map')
        if msg is None:
            return 0.0
        info = msg.info
        data = np.asarray(msg.data, np.int8).reshape(info.height, info.width)
        cell = np.floor((inside - (info.origin.position.x, info.origin.position.y)) / info.resolution).astype(int)
        ok = (cell[:, 0] >= 0) & (cell[:, 1] >= 0) & (cell[:, 0] < info.width) & (cell[:, 1] < info.height)
        return float((data[cell[ok, 1], cell[ok, 0]] >= 0).sum() / len(inside))
    with background_node('map_reader') as node:
        node.create_subscription(OccupancyGrid, '/map', lambda m: latest.__setitem__('map', m),
                                 QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL))
        nav.wait_for_output('Managed nodes are active', timeout=120)
        explore = spawn.command(sys.executable, '-m', 'zros', 'launch', 'explore_lite', 'explore.launch.py',
                                'use_sim_time:=True', name='explore')
        explore.wait_for_output('All frontiers traversed/tried out, stopping.', timeout=300)
        # SLAM publishes its map every few seconds: the one after the last goal is complete.
        wait_until(lambda: share_known() > 0.95, 30,
                   message=lambda: f'{share_known():.3f} of the room mapped\n{explore.output()[-3000:]}\n'
                                   f'{nav.output()[-4000:]}')
        explore.wait_for_output('Exploration finished, back at the initial pose.', timeout=120)
