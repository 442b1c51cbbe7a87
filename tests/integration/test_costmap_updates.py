"""A costmap sends its grid whole once, then only the rectangle that changed on
`<costmap>/costmap_updates` (Nav2's Costmap2DPublisher with always_send_full_costmap false); a
subscriber that pastes each update into the grid it holds (as RViz's Map display does) holds the
costmap as it is."""
from __future__ import annotations

import numpy as np

from zros.executors import SingleThreadedExecutor
from zros.grid_update import apply_update
from zros.navigation.costmap import to_occupancy
from zros.navigation.costmap_ros import CostmapNode
from zros.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from zros.testing import spin_until
from zros.tf2_ros import Buffer

from interfaces.map_msgs.msg import OccupancyGridUpdate
from interfaces.nav_msgs.msg import OccupancyGrid

LATCHED = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL, reliability=ReliabilityPolicy.RELIABLE)


def _map(cells: np.ndarray) -> OccupancyGrid:
    msg = OccupancyGrid()
    msg.header.frame_id = 'map'
    msg.info.resolution = 0.05
    msg.info.height, msg.info.width = cells.shape
    msg.info.origin.position.x, msg.info.origin.position.y = -1.0, -0.5
    msg.info.origin.orientation.w = 1.0
    msg.data = cells.ravel()
    return msg


class Viewer:
    """What RViz does with a costmap: hold the last whole grid and paste the updates into it."""

    def __init__(self, node) -> None:
        self.grid: np.ndarray | None = None
        self.wholes = 0
        self.updates: list[tuple[int, int]] = []   # (width, height) of each
        node.create_subscription(OccupancyGrid, '/global_costmap/costmap', self.on_grid, LATCHED)
        node.create_subscription(OccupancyGridUpdate, '/global_costmap/costmap_updates', self.on_update, LATCHED)

    def on_grid(self, msg) -> None:
        self.grid = np.array(msg.data, np.int8).reshape(msg.info.height, msg.info.width)
        self.wholes += 1

    def on_update(self, msg) -> None:
        if self.grid is not None:
            apply_update(self.grid, msg.x, msg.y, msg.width, msg.height, msg.data)
            self.updates.append((msg.width, msg.height))


def test_a_subscriber_pasting_the_updates_holds_the_costmap(zros_context, zros_node):
    source = zros_node('map_source')
    map_pub = source.create_publisher(OccupancyGrid, '/map', LATCHED)
    viewer_node = zros_node('viewer')
    viewer = Viewer(viewer_node)
    costmap = CostmapNode('global_costmap', default_frame='map', rolling=False, tf_buffer=Buffer())
    executor = SingleThreadedExecutor()
    for node in (source, viewer_node, costmap):
        executor.add_node(node)
    cells = np.zeros((60, 80), np.int8)
    cells[:, 0] = cells[:, -1] = 100
    map_pub.publish(_map(cells))
    spin_until(executor, lambda: costmap.ready, 10, message='the costmap has the map')

    def current() -> np.ndarray:
        with costmap.lock:
            return to_occupancy(costmap.costmap.master)
    spin_until(executor, lambda: costmap._grid_pub.get_subscription_count() >= 1, 10, message='the viewer in the graph')
    costmap.publish()
    spin_until(executor, lambda: viewer.grid is not None and np.array_equal(viewer.grid, current()), 10,
               message='the whole grid at the viewer')
    wholes = viewer.wholes

    cells[20:24, 30:33] = 100                     # a new obstacle, far from the walls' inflation
    map_pub.publish(_map(cells))
    spin_until(executor, lambda: not np.array_equal(viewer.grid, current()) or viewer.updates, 10,
               message='the costmap took the new map')
    costmap.publish()
    spin_until(executor, lambda: viewer.updates and np.array_equal(viewer.grid, current()), 10,
               message=lambda: f'the viewer pasted the update: {viewer.updates}')
    assert viewer.wholes == wholes                # no whole grid for a change of a few cells
    width, height = viewer.updates[-1]
    assert width * height < cells.size / 4        # the obstacle and its inflation, not the grid
    assert width > 3 and height > 4               # and the inflation round it

    updates = len(viewer.updates)
    costmap.publish()                             # nothing changed: nothing is sent
    for _ in range(5):
        executor.spin_once(timeout_sec=0.1)
    assert len(viewer.updates) == updates and viewer.wholes == wholes

    # a subscriber that joins now gets the grid whole, as it is (the latched one predates the update)
    late_node = zros_node('late_viewer')
    late = Viewer(late_node)
    executor.add_node(late_node)
    spin_until(executor, lambda: costmap._grid_pub.get_subscription_count() >= 2, 10, message='the late viewer')
    costmap.publish()
    spin_until(executor, lambda: late.grid is not None and np.array_equal(late.grid, current()), 10,
               message='the whole grid at the late viewer')
    spin_until(executor, lambda: viewer.wholes == wholes + 1, 10, message='the whole grid again at the first viewer')
    assert np.array_equal(viewer.grid, current())
