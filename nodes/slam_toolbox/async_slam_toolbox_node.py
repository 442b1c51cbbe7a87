"""async_slam_toolbox_node: online 2D SLAM in slam_toolbox's (and Cartographer's) role.

    zros launch slam_toolbox online_async_launch.py use_sim_time:=True
    zros launch turtlebot3_cartographer cartographer.launch.py use_sim_time:=True   # the same node
    zros service call /slam_toolbox/save_map slam_toolbox/srv/SaveMap "{name: {data: /tmp/map}}"

The algorithm is zros.slam (docs/slam.md): scans are matched against a local map, keyframes
form a pose graph closed by loop closures, and the map is a log-odds grid. This node feeds it:
each `/scan` with the odometry pose at the scan's stamp (TF `odom -> base_footprint`, waiting
up to `transform_timeout`), and the lidar's pose on the robot (TF `base_footprint ->
base_scan`, once). Scans arrive on the subscription thread and are processed on a worker
thread, latest first: a scan that comes while one is being processed replaces the waiting one
(slam_toolbox's asynchronous mode), so the node never falls behind.

Out: `map -> odom` on /tf every `transform_publish_period` wall seconds (stamped now +
`transform_timeout`, so lookups at the latest odometry time succeed, as slam_toolbox does);
`/map` (nav_msgs/OccupancyGrid) and `/map_metadata` (reliable, transient local) every
`map_update_interval` wall seconds when the map changed; `pose`
(PoseWithCovarianceStamped) after each scan. Services under the node's name:
`~/dynamic_map` (nav_msgs/GetMap), `~/save_map`, `~/serialize_map`, `~/deserialize_map`,
`~/pause_new_measurements` (slam_toolbox/srv/*).

A lifecycle node (`slam_toolbox/get_state`, `change_state`, ...) that works only while
active, as Jazzy's slam_toolbox. Started the Humble way (`zros run`, a launch file's `Node`,
zros's own launch files) it configures and activates itself at once, so it maps as Humble's
does and answers `active`; started by a launch file's `LifecycleNode` (Jazzy's
online_async_launch.py) or with `use_lifecycle_manager: true`, it waits in `unconfigured` for
the launch's ChangeState events or a lifecycle manager (zros.lifecycle.autostart).

Parameters: the frames and timing above (slam_toolbox's names and defaults where they
exist), `mode` (mapping or localization: the executable decides, as in slam_toolbox),
`use_lifecycle_manager` (false), every field of zros.slam.SlamParameters by its name, and
`map_file_name` with `map_start_pose` [x, y, theta] or `map_start_at_dock`: a serialized graph
loaded at configure, as `deserialize_map` would (mapping goes on in it: lifelong mapping). A parameter of the wrong type or out of range stops the
node with one line naming it (when it waits for transitions: fails `configure`, and says why).
"""
from __future__ import annotations

import sys
import threading
from dataclasses import fields
from typing import Any

import numpy as np

import zros
from zros.clock import Clock, ClockType
from zros.duration import Duration
from zros.errors import CliError
from zros.exceptions import ParameterUninitializedException
from zros.executors import ExternalShutdownException, spin_nodes
from zros.lifecycle import LifecycleNodeMixin, State, TransitionCallbackReturn
from zros.lifecycle.autostart import waits_for_transitions
from zros.map_io import MapFileError, map_to_msg, save_map
from zros.node import Node
from zros.parameter import Parameter
from zros.qos import DurabilityPolicy, QoSProfile, qos_profile_sensor_data
from zros.rotations import quaternion_from_yaw, yaw_from_quaternion
from zros.slam import PoseGraphFileError, Slam, SlamParameters, scan_points
from zros.tf2_ros import Buffer, TransformBroadcaster, TransformException, TransformListener
from zros.time import Time

from interfaces.geometry_msgs.msg import PoseWithCovarianceStamped, TransformStamped
from interfaces.nav_msgs.msg import MapMetaData, OccupancyGrid
from interfaces.nav_msgs.srv import GetMap
from interfaces.sensor_msgs.msg import LaserScan
from interfaces.slam_toolbox.srv import DeserializePoseGraph, Pause, SaveMap, SerializePoseGraph

__all__ = ['SlamNode', 'main']

MAP_QOS = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL)
#: [s] stamps this close to `minimum_time_interval` count as reaching it (5 Hz scans 0.2 s apart).
_STAMP_SLACK_S = 0.005
#: The node's own parameters and defaults (slam_toolbox's names; zros's defaults where noted).
NODE_PARAMETERS: dict[str, Any] = {
    'odom_frame': 'odom', 'map_frame': 'map', 'base_frame': 'base_footprint', 'scan_topic': '/scan',
    'mode': 'mapping',
    'map_update_interval': 5.0,          # [s, wall] between /map publications
    'transform_publish_period': 0.02,    # [s, wall] between map -> odom publications (0: none)
    'transform_timeout': 0.2,            # [s] wait for odometry at a scan's stamp; future-dating of map -> odom
    'minimum_time_interval': 0.2,        # [s] scans closer than this (scan time) are skipped (slam_toolbox: 0.5)
    'map_file_name': '',                 # a serialized pose graph to start in ('' none)
}
#: Parameters that are unset unless given (slam_toolbox tells "not given" from any value).
START_PARAMETERS = {'map_start_pose': Parameter.Type.DOUBLE_ARRAY, 'map_start_at_dock': Parameter.Type.BOOL}


class SlamNode(LifecycleNodeMixin, Node):
    """The ROS face of zros.slam.Slam (module docstring). Subclasses change the mode:
    `LOCALIZING` (a fixed map) and `START_MATCH_TYPE` (how `map_file_name` is loaded)."""

    LOCALIZING = False

    def __init__(self, node_name: str = 'slam_toolbox', *, publish_map: bool = True, **kwargs: Any) -> None:
        """`publish_map`: publish /map and /map_metadata (cartographer_ros's cartographer_node
        leaves that to its occupancy grid node, which reads `~/dynamic_map`)."""
        Node.__init__(self, node_name, **kwargs)
        self._map_publishing = publish_map
        self._wake = threading.Condition()
        self._stopping = False
        self._active = False
        self._worker: threading.Thread | None = None
        self._entities: list[Any] = []
        for name, default in NODE_PARAMETERS.items():
            self.declare_parameter(name, default)
        for name, kind in START_PARAMETERS.items():
            self.declare_parameter(name, kind)
        defaults = SlamParameters()
        for f in fields(SlamParameters):
            self.declare_parameter(f.name, getattr(defaults, f.name))
        managed = self.declare_parameter('use_lifecycle_manager', False).value
        waits = waits_for_transitions(use_lifecycle_manager=bool(managed))
        if not waits:
            self._settings()   # a bad parameter stops the node here, with one line
        # The lifecycle services last: whoever drives the node calls them as soon as they appear.
        LifecycleNodeMixin.__init__(self)
        if waits:
            self.get_logger().info('Waiting unconfigured for its lifecycle transitions (configure, activate) '
                                   'from the launch or a lifecycle manager')
        else:
            self.trigger_configure()
            self.trigger_activate()

    def _settings(self) -> tuple[dict[str, Any], SlamParameters]:
        """The node's parameters and the algorithm's, checked; CliError names a bad one."""
        values = {name: self.get_parameter(name).value for name in NODE_PARAMETERS}
        self._check_node_parameters(values)
        try:
            return values, SlamParameters(**{f.name: self.get_parameter(f.name).value for f in fields(SlamParameters)})
        except ValueError as exc:
            raise CliError(f'{self.get_name()}: parameter {exc}') from None

    def _check_node_parameters(self, p: dict[str, Any]) -> None:
        if p['mode'] not in ('mapping', 'localization'):
            raise CliError(f"{self.get_name()}: parameter 'mode': 'mapping' or 'localization', got {p['mode']!r}")
        for name in ('map_update_interval', 'transform_timeout'):
            if not p[name] > 0:
                raise CliError(f"{self.get_name()}: parameter '{name}' must be > 0 [s], got {p[name]!r}")
        for name in ('transform_publish_period', 'minimum_time_interval'):
            if p[name] < 0:
                raise CliError(f"{self.get_name()}: parameter '{name}' must be >= 0 [s], got {p[name]!r}")

    # -- lifecycle -------------------------------------------------------------------------------
    def on_configure(self, state: State) -> TransitionCallbackReturn:
        try:
            self._p, parameters = self._settings()
        except CliError as exc:
            self.get_logger().error(f'Cannot configure: {exc}')
            return TransitionCallbackReturn.FAILURE
        self._slam = Slam(parameters)
        self._lock = threading.Lock()                 # around self._slam (not thread-safe)
        self._pending: LaserScan | None = None
        self._paused = False
        self._sensor_pose: tuple[float, float, float] | None = None
        self._last_scan_time: float | None = None
        self._map_to_odom: np.ndarray | None = None
        self._map_stale = False
        self._warned: set[str] = set()

        self._tf_buffer = Buffer(node=self, cache_time=Duration(seconds=30.0))
        self._tf_listener = TransformListener(self._tf_buffer, self)
        self._tf_broadcaster = TransformBroadcaster(self)
        self._map_pub = self.create_publisher(OccupancyGrid, 'map', MAP_QOS)
        self._metadata_pub = self.create_publisher(MapMetaData, 'map_metadata', MAP_QOS)
        self._pose_pub = self.create_publisher(PoseWithCovarianceStamped, 'pose', 10)
        keep = self._entities.append
        for entity in (self._map_pub, self._metadata_pub, self._pose_pub, self._tf_broadcaster.pub_tf):
            keep(entity)
        keep(self.create_subscription(LaserScan, self._p['scan_topic'], self._on_scan, qos_profile_sensor_data))
        keep(self.create_service(GetMap, '~/dynamic_map', self._on_dynamic_map))
        keep(self.create_service(SerializePoseGraph, '~/serialize_map', self._on_serialize))
        keep(self.create_service(DeserializePoseGraph, '~/deserialize_map', self._on_deserialize))
        keep(self.create_service(Pause, '~/pause_new_measurements', self._on_pause))
        self._create_mode_entities(keep)
        wall = Clock(clock_type=ClockType.STEADY_TIME)
        if self._map_publishing:
            keep(self.create_timer(self._p['map_update_interval'], self._publish_map, clock=wall))
        if self._p['transform_publish_period'] > 0:
            keep(self.create_timer(self._p['transform_publish_period'], self._publish_transform, clock=wall))
        self._stopping = False
        self._worker = threading.Thread(target=self._work, name='slam', daemon=True)
        self._worker.start()
        doing = 'Localizing' if self.LOCALIZING else 'Mapping'
        self.get_logger().info(f"{doing} at {parameters.resolution:g} m/cell from '{self._p['scan_topic']}' "
                               f"({self._p['odom_frame']} -> {self._p['base_frame']}); map -> odom on /tf")
        self._load_by_parameters()
        return TransitionCallbackReturn.SUCCESS

    def _create_mode_entities(self, keep: Any) -> None:
        """What mapping has and localization has not: slam_toolbox's map saver service."""
        keep(self.create_service(SaveMap, '~/save_map', self._on_save_map))

    def _load_by_parameters(self) -> None:
        """`map_file_name` given: load it as slam_toolbox does at start, at `map_start_pose` or at
        its first node (`map_start_at_dock`); with neither, say so and map from scratch."""
        filename = self._p['map_file_name']
        if not filename:
            return
        pose, dock = (self._given(name) for name in START_PARAMETERS)
        if pose is not None:
            if len(pose) != 3:
                self.get_logger().error('map_start_pose must be [x, y, theta]; starting at the origin')
                pose = (0.0, 0.0, 0.0)
        elif dock is None:
            self.get_logger().error('map_file_name is set but not where to start in it: set map_start_pose or '
                                    'map_start_at_dock; the map is not loaded')
            return
        elif not dock:
            pose = (0.0, 0.0, 0.0)       # slam_toolbox: map_start_at_dock false starts at the origin
        self._load(filename, pose=None if pose is None else tuple(pose))

    def _given(self, name: str) -> Any:
        """A START_PARAMETERS value, None when not given."""
        try:
            return self.get_parameter(name).value
        except ParameterUninitializedException:
            return None

    def _load(self, filename: str, *, pose: tuple[float, float, float] | None) -> bool:
        """Load a serialized graph (at `pose`, or at its first node), in this node's mode."""
        try:
            with self._lock:
                path = self._slam.deserialize(filename, pose=pose, localize=self.LOCALIZING)
                self._last_scan_time = None
        except PoseGraphFileError as exc:
            self.get_logger().error(f'Cannot load the pose graph, the current map is kept: {exc}')
            return False
        self._map_stale = True
        where = 'its first node' if pose is None else f'({pose[0]:.2f}, {pose[1]:.2f}), theta={pose[2]:.2f}'
        self.get_logger().info(f'Pose graph loaded from {path}: {len(self._slam.keyframes)} nodes; '
                               f'{"localizing" if self.LOCALIZING else "mapping"} from {where}')
        return True

    def on_activate(self, state: State) -> TransitionCallbackReturn:
        self._active = True
        return super().on_activate(state)

    def on_deactivate(self, state: State) -> TransitionCallbackReturn:
        self._active = False
        return super().on_deactivate(state)

    def on_cleanup(self, state: State) -> TransitionCallbackReturn:
        self._release()
        return super().on_cleanup(state)

    def on_shutdown(self, state: State) -> TransitionCallbackReturn:
        self._release()
        return super().on_shutdown(state)

    def _release(self) -> None:
        """Undo on_configure: stop the worker, destroy what it created."""
        self._active = False
        self._stop_worker()
        for entity in reversed(self._entities):
            self._destroy_entity(entity)
        self._entities.clear()
        if hasattr(self, '_tf_listener'):
            self._tf_listener.unregister()
            del self._tf_listener

    def _stop_worker(self) -> None:
        with self._wake:
            self._stopping = True
            self._wake.notify()
        if self._worker is not None:
            self._worker.join(timeout=2.0)
            self._worker = None

    def destroy_node(self) -> None:
        self._stop_worker()
        super().destroy_node()

    # -- scans ----------------------------------------------------------------------------------
    def _on_scan(self, msg: LaserScan) -> None:
        if self._paused or not self._active:
            return
        with self._wake:
            self._pending = msg
            self._wake.notify()

    def _work(self) -> None:
        while True:
            with self._wake:
                while self._pending is None and not self._stopping:
                    self._wake.wait()
                if self._stopping:
                    return
                msg, self._pending = self._pending, None
            try:
                self._process(msg)
            except Exception as exc:  # noqa: BLE001 - one bad scan must not end mapping; say why once
                self._warn_once('process', f'a scan could not be processed: {type(exc).__name__}: {exc}')

    def _process(self, msg: LaserScan) -> None:
        stamp = Time.from_msg(msg.header.stamp)
        scan_time = stamp.nanoseconds * 1e-9
        since = None if self._last_scan_time is None else scan_time - self._last_scan_time
        if since is not None and 0 <= since < self._p['minimum_time_interval'] - _STAMP_SLACK_S:
            return
        odom = self._odometry_pose(msg, stamp)
        if odom is None:
            return
        points = scan_points(msg.ranges, msg.angle_min, msg.angle_increment, range_min=msg.range_min,
                             range_max=msg.range_max, sensor_pose=self._sensor_pose,
                             max_range=self._slam.parameters.max_laser_range,
                             missing_data_ray_length=self._slam.parameters.missing_data_ray_length)
        with self._lock:
            update = self._slam.process_scan(odom, points)
        self._last_scan_time = scan_time
        self._map_to_odom = update.map_to_odom
        self._map_stale = self._map_stale or update.keyframe
        self._publish_pose(update.pose, msg.header.stamp)

    def _odometry_pose(self, msg: LaserScan, stamp: Time) -> np.ndarray | None:
        """The odometry pose (x, y, yaw) at the scan's stamp, and the lidar's mounting (first
        time); None (and one warning saying why) while TF cannot tell."""
        odom_frame, base_frame = self._p['odom_frame'], self._p['base_frame']
        try:
            if self._sensor_pose is None:
                mount = self._tf_buffer.lookup_transform(base_frame, msg.header.frame_id, Time(),
                                                         timeout=Duration(seconds=self._p['transform_timeout']))
                self._sensor_pose = _pose2d(mount)
            odom = self._tf_buffer.lookup_transform(odom_frame, base_frame, stamp,
                                                    timeout=Duration(seconds=self._p['transform_timeout']))
        except TransformException as exc:
            self._warn_once('tf', f"waiting for TF {odom_frame} -> {base_frame} -> {msg.header.frame_id} at the "
                                  f'scan stamps ({exc}); scans are skipped until it comes')
            return None
        return np.array(_pose2d(odom))

    def _warn_once(self, key: str, text: str) -> None:
        if key not in self._warned:
            self._warned.add(key)
            self.get_logger().warn(text)

    # -- outputs --------------------------------------------------------------------------------
    def _publish_transform(self) -> None:
        if self._map_to_odom is None or not self._active:
            return
        x, y, yaw = self._map_to_odom
        t = TransformStamped()
        t.header.stamp = (self.get_clock().now() + Duration(seconds=self._p['transform_timeout'])).to_msg()
        t.header.frame_id, t.child_frame_id = self._p['map_frame'], self._p['odom_frame']
        t.transform.translation.x, t.transform.translation.y = float(x), float(y)
        r = t.transform.rotation
        r.x, r.y, r.z, r.w = quaternion_from_yaw(float(yaw))
        self._tf_broadcaster.sendTransform(t)

    def _publish_pose(self, pose: np.ndarray, stamp: Any) -> None:
        msg = PoseWithCovarianceStamped()
        msg.header.stamp, msg.header.frame_id = stamp, self._p['map_frame']
        msg.pose.pose.position.x, msg.pose.pose.position.y = float(pose[0]), float(pose[1])
        q = msg.pose.pose.orientation
        q.x, q.y, q.z, q.w = quaternion_from_yaw(float(pose[2]))
        self._pose_pub.publish(msg)

    def _current_map(self) -> OccupancyGrid:
        with self._lock:
            grid = self._slam.occupancy_map()
        return map_to_msg(grid, frame_id=self._p['map_frame'], stamp=self.get_clock().now().to_msg())

    def _publish_map(self) -> None:
        if not self._map_stale or not self._active:
            return
        self._map_stale = False
        msg = self._current_map()
        self._map_pub.publish(msg)
        self._metadata_pub.publish(msg.info)

    # -- services -------------------------------------------------------------------------------
    def _on_dynamic_map(self, request: Any, response: Any) -> Any:
        response.map = self._current_map()
        return response

    def _on_save_map(self, request: Any, response: Any) -> Any:
        name = request.name.data or 'map'
        if not self._slam.keyframes:
            self.get_logger().warn('save_map: no map yet (no scan has been processed)')
            response.result = response.RESULT_NO_MAP_RECEIEVD
            return response
        with self._lock:
            grid = self._slam.occupancy_map()
        try:
            yaml_path, _ = save_map(grid, name)
        except MapFileError as exc:
            self.get_logger().error(f'save_map failed: {exc}')
            response.result = response.RESULT_UNDEFINED_FAILURE
            return response
        self.get_logger().info(f'Map saved to {yaml_path}')
        response.result = response.RESULT_SUCCESS
        return response

    def _on_serialize(self, request: Any, response: Any) -> Any:
        try:
            with self._lock:
                path, _ = self._slam.serialize(request.filename or 'map')
        except PoseGraphFileError as exc:
            self.get_logger().error(f'serialize_map failed: {exc}')
            response.result = response.RESULT_UNDEFINED_FAILURE
            return response
        self.get_logger().info(f'Pose graph ({len(self._slam.keyframes)} nodes) saved to {path} and .data')
        response.result = response.RESULT_SUCCESS
        return response

    #: deserialize_map's match types this mode takes.
    MATCH_TYPES = {DeserializePoseGraph.Request.START_AT_FIRST_NODE: 'START_AT_FIRST_NODE',
                   DeserializePoseGraph.Request.START_AT_GIVEN_POSE: 'START_AT_GIVEN_POSE'}

    def _on_deserialize(self, request: Any, response: Any) -> Any:
        kind = request.match_type
        if kind not in self.MATCH_TYPES:
            taken = ', '.join(f'{k}: {name}' for k, name in self.MATCH_TYPES.items())
            self.get_logger().error(f'deserialize_map: match_type {kind} is not taken in this mode ({taken})')
            return response
        if not request.filename:
            self.get_logger().warn('deserialize_map: no map file given')
            return response
        pose = None
        if kind != request.START_AT_FIRST_NODE:
            pose = (request.initial_pose.x, request.initial_pose.y, request.initial_pose.theta)
        self._load(request.filename, pose=pose)
        return response

    def _on_pause(self, request: Any, response: Any) -> Any:
        self._paused = not self._paused
        self.get_logger().info('Processing of new measurements ' + ('paused' if self._paused else 'resumed'))
        response.status = True
        return response


def _pose2d(transform: TransformStamped) -> tuple[float, float, float]:
    t = transform.transform
    r = t.rotation
    return float(t.translation.x), float(t.translation.y), yaw_from_quaternion(r.x, r.y, r.z, r.w)


def main(args: list[str] | None = None, *, node_class: type[SlamNode] = SlamNode) -> int:
    """Run the node (`node_class`: the mode's SlamNode subclass) until Ctrl-C."""
    try:
        with zros.init(args=args):
            spin_nodes(node_class())
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    return 0


if __name__ == '__main__':
    sys.exit(main())
