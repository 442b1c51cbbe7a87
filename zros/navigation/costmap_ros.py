"""Costmap2DROS's role: a LayeredCostmap wired to /map, /scan and TF, published for the view.

It is a node of its own (`global_costmap` in namespace `global_costmap`, `local_costmap` in
`local_costmap`), living in the process of the server that uses it, as in Nav2, so that Nav2's
parameter files (`global_costmap: global_costmap: ros__parameters: ...`) apply unchanged. It
publishes `<name>/costmap` (nav_msgs/OccupancyGrid, Nav2's cost-to-occupancy table),
`<name>/costmap_updates` (map_msgs/OccupancyGridUpdate: the rectangle that changed, see
`CostmapNode.publish`), `<name>/costmap_raw` (nav2_msgs/Costmap) and `<name>/published_footprint`
(the round footprint of `robot_radius` at the robot's pose, geometry_msgs/PolygonStamped in the
costmap's frame: a collision monitor's `footprint_topic` takes the robot's shape from it), and
serves `<name>/clear_entirely_<name>`,
`clear_except_<name>`, `clear_around_<name>` and `clear_around_pose_<name>` (also under the
`clear_costmap_*` names Jazzy's BasicNavigator calls).

Servers that only read a costmap another node keeps (behavior_server, smoother_server) use
`CostmapSubscriber` on its `costmap_raw` topic, as Nav2's nav2_costmap_2d::CostmapSubscriber.
"""
from __future__ import annotations

import threading
from typing import Any, Callable

import numpy as np

from zros.grid_update import changed_bounds, patch
from zros.navigation.costmap import (NO_INFORMATION, CostmapParams, LayeredCostmap, footprint_from_radius,
                                     to_occupancy)
from zros.navigation.node_support import Nav2Params, lookup_pose
from zros.node import Node
from zros.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy, qos_profile_sensor_data

__all__ = ['CostmapNode', 'CostmapSubscriber']


class CostmapNode(Node):
    """One costmap; `on_update` runs after each rebuild of the master grid (planner cache)."""

    def __init__(self, name: str, *, default_frame: str, rolling: bool, tf_buffer: Any,
                 on_update: Callable[[], None] | None = None) -> None:
        # Node-specific rules: a launch file's `__node:=planner_server` for the process must not
        # rename the costmap too (Nav2 does the same with its costmap's NodeOptions).
        super().__init__(name, namespace=name,
                         cli_args=['--ros-args', '-r', f'{name}:__node:={name}', '-r', f'{name}:__ns:=/{name}'])
        self.tf_buffer = tf_buffer
        self.on_update = on_update
        self.lock = threading.RLock()
        prm = Nav2Params(self)
        self.global_frame = prm.get('global_frame', default_frame)
        self.robot_base_frame = prm.get('robot_base_frame', 'base_link')
        update_frequency = prm.get('update_frequency', 5.0 if rolling else 1.0)
        publish_frequency = prm.get('publish_frequency', 2.0 if rolling else 1.0)
        self.always_send_full_costmap = prm.get('always_send_full_costmap', False)
        plugins = prm.get('plugins', ['voxel_layer', 'inflation_layer'] if rolling
                          else ['static_layer', 'obstacle_layer', 'inflation_layer'])
        kinds = {name: self._kind(prm, name) for name in plugins}
        obstacle = next((n for n, k in kinds.items() if k == 'obstacle'), None)
        inflation = next((n for n, k in kinds.items() if k == 'inflation'), None)
        static = next((n for n, k in kinds.items() if k == 'static'), None)
        params = CostmapParams(
            resolution=prm.get('resolution', 0.05),
            width=float(prm.get('width', 3.0)), height=float(prm.get('height', 3.0)),
            rolling_window=prm.get('rolling_window', rolling),
            robot_radius=prm.get('robot_radius', 0.1),
            track_unknown_space=prm.get('track_unknown_space', not rolling),
            lethal_cost_threshold=prm.get('lethal_cost_threshold', 100),
            trinary_costmap=prm.get('trinary_costmap', True),
            use_static_layer=static is not None, use_obstacle_layer=obstacle is not None,
            use_inflation_layer=inflation is not None)
        self.scan_topic = '/scan'
        if obstacle:
            sources = prm.get(f'{obstacle}.observation_sources', 'scan').split()
            source = sources[0] if sources else 'scan'
            self.scan_topic = prm.get(f'{obstacle}.{source}.topic', '/scan')
            params.obstacle_max_range = prm.get(f'{obstacle}.{source}.obstacle_max_range',
                                                prm.get(f'{obstacle}.{source}.obstacle_range', 2.5))
            params.raytrace_max_range = prm.get(f'{obstacle}.{source}.raytrace_max_range',
                                                prm.get(f'{obstacle}.{source}.raytrace_range', 3.0))
        if inflation:
            params.inflation_radius = prm.get(f'{inflation}.inflation_radius', 0.55)
            params.cost_scaling_factor = prm.get(f'{inflation}.cost_scaling_factor', 10.0)
            params.inflate_unknown = prm.get(f'{inflation}.inflate_unknown', False)
        self.params = params
        self.costmap = LayeredCostmap(params)
        self._have_map = static is None
        self._scan_frame_warned = False
        latched = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL, reliability=ReliabilityPolicy.RELIABLE)
        from interfaces.map_msgs.msg import OccupancyGridUpdate
        from interfaces.nav2_msgs.msg import Costmap
        from interfaces.nav2_msgs.srv import ClearEntireCostmap, GetCostmap
        from interfaces.nav_msgs.msg import OccupancyGrid
        from interfaces.sensor_msgs.msg import LaserScan
        self._grid_pub = self.create_publisher(OccupancyGrid, 'costmap', latched)
        self._update_pub = self.create_publisher(OccupancyGridUpdate, 'costmap_updates', latched)
        self._sent: np.ndarray | None = None      # the occupancy grid the subscribers hold now
        self._sent_placement: tuple | None = None  # its resolution and origin
        self._grid_subscribers = 0
        self._raw_pub = self.create_publisher(Costmap, 'costmap_raw', latched)
        from interfaces.geometry_msgs.msg import PolygonStamped
        self._footprint_pub = self.create_publisher(PolygonStamped, 'published_footprint', 1)
        if static:
            topic = prm.get(f'{static}.map_topic', '/map')
            self.create_subscription(OccupancyGrid, topic, self._on_map, latched)
        if obstacle:
            # Sensor QoS, as Nav2's obstacle layer: best effort takes scans from either kind of publisher.
            self.create_subscription(LaserScan, self.scan_topic, self._on_scan, qos_profile_sensor_data)
        self.create_service(ClearEntireCostmap, f'clear_entirely_{name}', self._on_clear)
        from interfaces.nav2_msgs.srv import ClearCostmapAroundPose, ClearCostmapAroundRobot, ClearCostmapExceptRegion
        # Nav2's names, and the ones Jazzy's BasicNavigator calls (clear_costmap_*), which Nav2's
        # own costmaps do not serve
        for prefix in (f'clear_except_{name}', 'clear_costmap_except_region'):
            self.create_service(ClearCostmapExceptRegion, prefix, lambda q, r: self._clear_square(q, r, outside=True))
        for prefix in (f'clear_around_{name}', 'clear_costmap_around_robot'):
            self.create_service(ClearCostmapAroundRobot, prefix, lambda q, r: self._clear_square(q, r, outside=False))
        for prefix in (f'clear_around_pose_{name}', 'clear_costmap_around_pose'):
            self.create_service(ClearCostmapAroundPose, prefix, self._clear_around_pose)
        self.create_service(GetCostmap, 'get_costmap', self._on_get_costmap)
        self.create_timer(1.0 / max(update_frequency, 0.1), self.update)
        self.create_timer(1.0 / max(publish_frequency, 0.1), self.publish)
        prm.report_unused()

    @staticmethod
    def _kind(prm: Nav2Params, layer: str) -> str:
        plugin = prm.get(f'{layer}.plugin', '')
        for key, kind in (('Static', 'static'), ('Obstacle', 'obstacle'), ('Voxel', 'obstacle'),
                          ('Inflation', 'inflation')):
            if key in plugin or key.lower() in layer:
                return kind
        return 'unknown'

    # -- inputs ------------------------------------------------------------------------------
    def _on_map(self, msg: Any) -> None:
        data = np.asarray(msg.data, np.int8).reshape(msg.info.height, msg.info.width)
        origin = (msg.info.origin.position.x, msg.info.origin.position.y)
        with self.lock:
            self.costmap.set_static_map(data, msg.info.resolution, origin)
            self._have_map = True
        self.update()

    def _on_scan(self, msg: Any) -> None:
        try:
            x, y, yaw = lookup_pose(self.tf_buffer, self.global_frame, msg.header.frame_id)
        except Exception as exc:  # noqa: BLE001 - tf2's exceptions: no transform yet
            self.get_logger().warn(f'Costmap waiting for transform {self.global_frame} -> {msg.header.frame_id}: {exc}',
                                   throttle_duration_sec=5.0)
            return
        ranges = np.asarray(msg.ranges, np.float64)
        angles = yaw + msg.angle_min + msg.angle_increment * np.arange(len(ranges))
        with self.lock:
            self.costmap.add_scan((x, y), angles, ranges, msg.range_min, msg.range_max)

    def _on_clear(self, request: Any, response: Any) -> Any:
        with self.lock:
            self.costmap.clear()
        self.update()
        self.get_logger().info(f'Received request to clear entirely the {self.get_name()}')
        return response

    def _clear_square(self, request: Any, response: Any, *, outside: bool) -> Any:
        try:
            x, y, _ = self.robot_pose()
        except Exception:  # noqa: BLE001 - tf2's exceptions
            self.get_logger().error('Cannot clear map because robot pose cannot be retrieved.')
            return response
        with self.lock:
            self.costmap.clear_square((x, y), float(request.reset_distance), outside=outside)
        self.update()
        return response

    def _clear_around_pose(self, request: Any, response: Any) -> Any:
        pose = request.pose
        frame = pose.header.frame_id or self.global_frame
        try:
            fx, fy, fyaw = lookup_pose(self.tf_buffer, self.global_frame, frame)
        except Exception:  # noqa: BLE001 - tf2's exceptions
            self.get_logger().error(f'Cannot clear map around a pose in {frame!r}: no transform to {self.global_frame!r}')
            return response
        px, py = pose.pose.position.x, pose.pose.position.y
        centre = (fx + px * np.cos(fyaw) - py * np.sin(fyaw), fy + px * np.sin(fyaw) + py * np.cos(fyaw))
        with self.lock:
            self.costmap.clear_square(centre, float(request.reset_distance))
        self.update()
        return response

    def _on_get_costmap(self, request: Any, response: Any) -> Any:
        response.map = self._messages()[1]
        return response

    # -- outputs -----------------------------------------------------------------------------
    def robot_pose(self) -> tuple[float, float, float]:
        return lookup_pose(self.tf_buffer, self.global_frame, self.robot_base_frame)

    @property
    def ready(self) -> bool:
        return self._have_map

    def update(self) -> None:
        if self.params.rolling_window:
            try:
                x, y, _ = self.robot_pose()
            except Exception:  # noqa: BLE001 - no TF yet: keep the window where it is
                return
            with self.lock:
                self.costmap.move_to(x, y)
        with self.lock:
            if not self._have_map:
                return
            self.costmap.update()
        if self.on_update is not None:
            self.on_update()

    def cost_at(self, xy: np.ndarray) -> np.ndarray:
        with self.lock:
            return self.costmap.cost_at(xy)

    def publish(self) -> None:
        """Publish the raw costmap, and the occupancy grid whole or as the rectangle that changed.

        As Nav2's Costmap2DPublisher: the grid goes whole the first time, when its size,
        resolution or origin changed (a rolling window that moved), and every time with
        `always_send_full_costmap`; otherwise only the cells that changed since, on
        `costmap_updates`, nothing when none did. Nav2 takes the rectangle from its layers'
        bounds of change; here it is the smallest one holding every cell whose value differs
        from what the subscribers hold, so it is never larger. Unlike Humble's, the grid also
        goes whole when a subscriber joined since the last publish (the graph counts them): a
        late subscriber's latched grid may be older than the updates sent since it. The footprint
        goes out every time, map or not."""
        self.publish_footprint()
        if not self._have_map:
            return
        grid, raw = self._messages()
        self._raw_pub.publish(raw)
        occupancy = np.asarray(grid.data).reshape(grid.info.height, grid.info.width)
        placement = (grid.info.resolution, grid.info.origin.position.x, grid.info.origin.position.y)
        subscribers = self._grid_pub.get_subscription_count()
        whole = (self.always_send_full_costmap or self._sent is None or self._sent.shape != occupancy.shape
                 or placement != self._sent_placement or subscribers > self._grid_subscribers)
        self._grid_subscribers = subscribers
        if whole:
            self._grid_pub.publish(grid)
        else:
            bounds = changed_bounds(self._sent, occupancy)
            if bounds is not None:
                from interfaces.map_msgs.msg import OccupancyGridUpdate
                update = OccupancyGridUpdate(header=grid.header, x=bounds.x0, y=bounds.y0, width=bounds.width,
                                             height=bounds.height, data=patch(occupancy, bounds))
                self._update_pub.publish(update)
        self._sent, self._sent_placement = occupancy, placement

    def publish_footprint(self) -> None:
        """The footprint at the robot's pose (nothing while TF has no pose for it)."""
        from interfaces.geometry_msgs.msg import Point32, PolygonStamped
        try:
            pose = self.robot_pose()
        except Exception:  # noqa: BLE001 - tf2's exceptions: no pose yet
            return
        msg = PolygonStamped()
        msg.header.frame_id = self.global_frame
        msg.header.stamp = self.get_clock().now().to_msg()
        msg.polygon.points = [Point32(x=float(x), y=float(y), z=0.0)
                              for x, y in footprint_from_radius(self.params.robot_radius, pose)]
        self._footprint_pub.publish(msg)

    def _messages(self) -> tuple[Any, Any]:
        """The master grid as (nav_msgs/OccupancyGrid, nav2_msgs/Costmap)."""
        from interfaces.nav2_msgs.msg import Costmap
        from interfaces.nav_msgs.msg import OccupancyGrid
        with self.lock:
            master = self.costmap.master.copy()
            origin = self.costmap.origin.copy()
            resolution = self.costmap.resolution
        stamp = self.get_clock().now().to_msg()
        grid = OccupancyGrid()
        grid.header.frame_id = self.global_frame
        grid.header.stamp = stamp
        grid.info.resolution = float(resolution)
        grid.info.height, grid.info.width = master.shape
        grid.info.origin.position.x, grid.info.origin.position.y = float(origin[0]), float(origin[1])
        grid.info.map_load_time = stamp
        grid.data = to_occupancy(master).ravel()
        raw = Costmap()
        raw.header = grid.header
        raw.metadata.resolution = grid.info.resolution
        raw.metadata.size_y, raw.metadata.size_x = master.shape
        raw.metadata.origin = grid.info.origin
        raw.metadata.update_time = stamp
        raw.metadata.layer = 'master'
        raw.data = master.ravel()
        return grid, raw



class CostmapSubscriber:
    """The latest nav2_msgs/Costmap on `topic` (transient local, as costmaps publish it), and
    costs looked up in it. Thread-safe: the subscription callback swaps the message under a lock."""

    def __init__(self, node: Any, topic: str) -> None:
        from interfaces.nav2_msgs.msg import Costmap
        self._lock = threading.Lock()
        self._msg: Any = None
        node.create_subscription(Costmap, topic, self._on_costmap,
                                 QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL))

    def _on_costmap(self, msg: Any) -> None:
        with self._lock:
            self._msg = msg

    @property
    def frame_id(self) -> str | None:
        """The costmap's frame, None before the first costmap arrives."""
        with self._lock:
            return None if self._msg is None else self._msg.header.frame_id

    def cost_at(self, xy: np.ndarray) -> np.ndarray | None:
        """Costs at (N, 2) points of the costmap's frame [m] (NO_INFORMATION outside it), or None
        before the first costmap arrives."""
        with self._lock:
            msg = self._msg
        if msg is None:
            return None
        md = msg.metadata
        grid = np.asarray(msg.data, np.uint8).reshape(md.size_y, md.size_x)
        cells = np.floor((np.asarray(xy, np.float64).reshape(-1, 2) - (md.origin.position.x, md.origin.position.y))
                         / md.resolution).astype(np.int64)
        inside = (cells[:, 0] >= 0) & (cells[:, 1] >= 0) & (cells[:, 0] < md.size_x) & (cells[:, 1] < md.size_y)
        out = np.full(len(cells), NO_INFORMATION, np.uint8)
        out[inside] = grid[cells[inside, 1], cells[inside, 0]]
        return out
