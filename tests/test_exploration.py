"""explore_lite's role end to end: the simulator in a small world that is unknown at the start,
a mapper that builds /map from the scans at the true pose (SLAM's role, without its errors), the
navigation servers, and `zros launch explore_lite explore.launch.py`: exploration ends by itself
("All frontiers traversed/tried out") with the map complete, then returns to its start."""
from __future__ import annotations

import math
import sys
import threading
from typing import Any

import numpy as np

from conftest import wait_until
from test_navigation_stack import _perfect_localization

WORLD = """
name: explore_room
spawn: {x: -1.2, y: -1.2, yaw: 0.0}
obstacles:
- ring: {center: [0, 0], sides: 4, inner_circumradius: 2.55, outer_circumradius: 2.83}
- box: {center: [0.0, -0.4], size: [0.3, 2.8], yaw: 0.0}
"""


def test_exploration_maps_the_world_and_stops(spawn: Any, context: Any, tmp_path: Any) -> None:
    from zros.executors import MultiThreadedExecutor
    from zros.navigation.costmap import FREE_SPACE, LETHAL_OBSTACLE, CostmapParams, LayeredCostmap
    from zros.navigation.node_support import yaw_of
    from zros.node import Node
    from zros.qos import DurabilityPolicy, QoSProfile
    from zros.sim import parse_world, rasterize
    from interfaces.nav_msgs.msg import OccupancyGrid, Odometry
    from interfaces.sensor_msgs.msg import LaserScan
    world_file = tmp_path / 'explore_room.yaml'
    world_file.write_text(WORLD)
    spawn.node('turtlebot3_gazebo', 'gzserver', '--ros-args', '-p', f'world:={world_file}', '-p', 'real_time_factor:=5.0')
    nav = spawn.command(sys.executable, '-m', 'zros', 'launch', 'nav2_bringup', 'navigation_launch.py',
                        'use_sim_time:=True', name='navigation')
    node = Node('mapper', context=context)
    truth: dict[str, Any] = {}
    _perfect_localization(node, truth)
    truth_raster = rasterize(parse_world(WORLD), 0.05)
    rows, cols = truth_raster.cells.shape
    mapper = LayeredCostmap(CostmapParams(use_static_layer=False, use_inflation_layer=False, track_unknown_space=True,
                                          width=cols * 0.05, height=rows * 0.05, obstacle_max_range=3.5,
                                          raytrace_max_range=3.5))
    mapper.origin = np.asarray(truth_raster.origin, np.float64)
    lock = threading.Lock()
    lidar_x = -0.032

    def on_scan(msg: Any) -> None:
        pose = truth.get('pose')
        if pose is None:
            return
        yaw = yaw_of(pose.orientation)
        x = pose.position.x + lidar_x * math.cos(yaw)
        y = pose.position.y + lidar_x * math.sin(yaw)
        ranges = np.asarray(msg.ranges, np.float64)
        angles = yaw + msg.angle_min + msg.angle_increment * np.arange(len(ranges))
        with lock:
            mapper.add_scan((x, y), angles, ranges, msg.range_min, msg.range_max)

    map_pub = node.create_publisher(OccupancyGrid, '/map', QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL))

    def publish_map() -> None:
        with lock:
            costs = mapper.update().copy()
        grid = OccupancyGrid()
        grid.header.frame_id = 'map'
        grid.header.stamp = node.get_clock().now().to_msg()
        grid.info.resolution = 0.05
        grid.info.height, grid.info.width = costs.shape
        grid.info.origin.position.x, grid.info.origin.position.y = map(float, mapper.origin)
        data = np.full(costs.shape, -1, np.int8)
        data[costs == FREE_SPACE] = 0
        data[costs == LETHAL_OBSTACLE] = 100
        grid.data = data.ravel()
        map_pub.publish(grid)
        truth['map'] = data
    node.create_subscription(LaserScan, '/scan', on_scan, 5)
    node.create_timer(1.0, publish_map)
    executor = MultiThreadedExecutor(num_threads=4, context=context)
    executor.add_node(node)
    threading.Thread(target=executor.spin, daemon=True).start()
    try:
        nav.wait_for_output('Managed nodes are active', timeout=120)
        explore = spawn.command(sys.executable, '-m', 'zros', 'launch', 'explore_lite', 'explore.launch.py',
                                'use_sim_time:=True', name='explore')
        explore.wait_for_output('All frontiers traversed/tried out, stopping.', timeout=240)
        # The free space inside the walls, as the exact raster says: is it all known in the map?
        from scipy import ndimage
        labels, _ = ndimage.label(~truth_raster.cells)
        row, col = truth_raster.cell_of(-1.2, -1.2)
        inside = labels == labels[row, col]
        share = ((truth['map'] >= 0) & inside).sum() / inside.sum()
        assert share > 0.95, f'{share}\n{explore.output()[-3000:]}\n{nav.output()[-5000:]}'
        explore.wait_for_output('Exploration finished, back at the initial pose.', timeout=120)
    finally:
        executor.shutdown(timeout_sec=2)
