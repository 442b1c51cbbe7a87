"""amcl: Nav2's AMCL node. Localizes the robot on a known map from its lidar and odometry.

    zros run nav2_amcl amcl --ros-args -p use_sim_time:=true        # then configure + activate it
    zros launch nav2_bringup localization_launch.py map:=$HOME/map.yaml   # the usual way

A lifecycle node, as in Nav2 (`amcl/get_state`, driven by lifecycle_manager_localization).
Subscribes `scan` (sensor-data QoS), `map` (transient local) and `initialpose`
(geometry_msgs/PoseWithCovarianceStamped); publishes `amcl_pose` (same type; reliable, transient
local, depth 1), `particle_cloud` (nav2_msgs/ParticleCloud, best effort; geometry_msgs/PoseArray
with `particle_cloud_type: PoseArray`), the `map -> odom` transform (stamped with the scan's
time plus `transform_tolerance`) and its own state on `/diagnostics`. Services:
`reinitialize_global_localization`, `request_nomotion_update` (std_srvs/Empty) and
`set_initial_pose` (nav2_msgs/SetInitialPose). Parameters: Nav2's names and defaults.

The filter itself is zros.amcl (numpy, no Zenoh); this node wires topics, TF and parameters to
it. Where Nav2 leaves beginners stuck, it talks: with no initial pose (or no map, or no scans)
it says what it waits for every few seconds and on /diagnostics, and publishes nothing until it
knows; bad input (NaN, an unknown frame) is dropped with one warning naming it.
"""
from __future__ import annotations

import math
import sys
import time
from typing import Any

import numpy as np

import zros
from zros.amcl import Amcl, AmclParameters, MapGrid
from zros.amcl.localizer import compose
from zros.clock import Clock, ClockType
from zros.duration import Duration
from zros.errors import CliError
from zros.executors import ExternalShutdownException
from zros.lifecycle import LifecycleNodeMixin, State, TransitionCallbackReturn
from zros.node import Node
from zros.parameter import Parameter
from zros.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy, qos_profile_sensor_data
from zros.rotations import quaternion_from_yaw, yaw_from_quaternion
from zros.tf2_ros import Buffer, TransformBroadcaster, TransformException, TransformListener
from zros.time import Time
from zros.tf_transformations import quaternion_matrix

from interfaces.diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue
from interfaces.geometry_msgs.msg import Pose, PoseArray, PoseWithCovarianceStamped, TransformStamped
from interfaces.nav2_msgs.msg import Particle, ParticleCloud
from interfaces.nav2_msgs.srv import SetInitialPose
from interfaces.nav_msgs.msg import OccupancyGrid
from interfaces.sensor_msgs.msg import LaserScan
from interfaces.std_srvs.srv import Empty

__all__ = ['AmclNode', 'main']

POSE_QOS = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL)
MAP_QOS = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL)
CLOUD_QOS = QoSProfile(depth=5, reliability=ReliabilityPolicy.BEST_EFFORT)
STATUS_PERIOD = 1.0        # [s] wall time between status checks (and /diagnostics)
NAG_PERIOD = 5.0           # [s] between log lines saying what the node waits for
TF_WAIT = 0.2              # [s] wall time a scan waits for odometry at its stamp

#: Node-level parameters (frames, topics, TF, start-up), with Nav2's names and defaults.
NODE_PARAMETERS: dict[str, Any] = {
    'base_frame_id': 'base_footprint', 'global_frame_id': 'map', 'odom_frame_id': 'odom',
    'scan_topic': 'scan', 'map_topic': 'map', 'tf_broadcast': True, 'transform_tolerance': 1.0,
    'save_pose_rate': 0.5, 'set_initial_pose': False, 'always_reset_initial_pose': False,
    'first_map_only': False, 'initial_pose.x': 0.0, 'initial_pose.y': 0.0, 'initial_pose.z': 0.0,
    'initial_pose.yaw': 0.0, 'particle_cloud_type': 'ParticleCloud',
    # Nav2 declares these for its beam model; the likelihood-field models do not use them.
    'lambda_short': 0.1, 'z_max': 0.05, 'z_short': 0.05,
}


class AmclNode(LifecycleNodeMixin, Node):

    def __init__(self, **kwargs: Any) -> None:
        Node.__init__(self, 'amcl', **kwargs)
        defaults = {**AmclParameters().__dict__, **NODE_PARAMETERS}
        for name, value in defaults.items():
            try:
                self.declare_parameter(name, value)
            except Exception as exc:  # noqa: BLE001 - a wrongly typed parameter file: one clear line
                raise CliError(f"amcl: parameter '{name}': {exc}") from None
        self._wall = Clock(clock_type=ClockType.STEADY_TIME)
        self._entities: list[Any] = []
        self._reset_state()
        # The lifecycle services last: a lifecycle manager calls them as soon as they appear,
        # and a call that arrives before the node spins can go unanswered.
        LifecycleNodeMixin.__init__(self)
        self.get_logger().info('Creating amcl (unconfigured: configure and activate it, or start it with '
                               'a lifecycle manager)')

    def _reset_state(self) -> None:
        self._amcl: Amcl | None = None
        self._active = False
        self._pending_pose: tuple[np.ndarray, np.ndarray] | None = None
        self._map_to_odom: np.ndarray | None = None
        self._last_scan_wall: float | None = None
        self._last_nag = -math.inf
        self._last_save = -math.inf
        self._laser_poses: dict[str, tuple[tuple[float, float, float], np.ndarray]] = {}
        self._bearings: dict[tuple, np.ndarray] = {}
        self._warned: set[str] = set()
        self._cloud_cache: list[Any] = []

    def _value(self, name: str) -> Any:
        return self.get_parameter(name).value

    # -- lifecycle -------------------------------------------------------------------------------------
    def on_configure(self, state: State) -> TransitionCallbackReturn:
        try:
            self.parameters = AmclParameters(**{name: type(default)(self._value(name))
                                                for name, default in AmclParameters().__dict__.items()})
            Amcl(self.parameters, MapGrid(np.zeros((3, 3)), resolution=1.0))      # checks names and ranges
            self._check_node_parameters()
        except (TypeError, ValueError) as exc:
            self.get_logger().error(f'Cannot configure amcl: {exc}')
            return TransitionCallbackReturn.FAILURE
        self._global_frame = self._value('global_frame_id').lstrip('/')
        self._odom_frame = self._value('odom_frame_id').lstrip('/')
        self._base_frame = self._value('base_frame_id').lstrip('/')
        self._tolerance = Duration(seconds=float(self._value('transform_tolerance')))
        keep = self._entities.append
        self._pose_pub = self.create_lifecycle_publisher(PoseWithCovarianceStamped, 'amcl_pose', POSE_QOS)
        self._cloud_type = ParticleCloud if self._value('particle_cloud_type') == 'ParticleCloud' else PoseArray
        self._cloud_pub = self.create_lifecycle_publisher(self._cloud_type, 'particle_cloud', CLOUD_QOS)
        self._diagnostics_pub = self.create_publisher(DiagnosticArray, '/diagnostics', 10)
        self._tf_buffer = Buffer()
        self._tf_listener = TransformListener(self._tf_buffer, self)
        self._tf_broadcaster = TransformBroadcaster(self)
        keep(self._diagnostics_pub)
        keep(self.create_subscription(OccupancyGrid, self._value('map_topic'), self._on_map, MAP_QOS))
        keep(self.create_subscription(LaserScan, self._value('scan_topic'), self._on_scan, qos_profile_sensor_data))
        keep(self.create_subscription(PoseWithCovarianceStamped, 'initialpose', self._on_initial_pose, 10))
        keep(self.create_service(Empty, 'reinitialize_global_localization', self._on_global_localization))
        keep(self.create_service(Empty, 'request_nomotion_update', self._on_nomotion_update))
        keep(self.create_service(SetInitialPose, 'set_initial_pose', self._on_set_initial_pose))
        keep(self.create_timer(STATUS_PERIOD, self._report_status, clock=self._wall))
        return TransitionCallbackReturn.SUCCESS

    def _check_node_parameters(self) -> None:
        for name in ('transform_tolerance', 'save_pose_rate'):
            value = float(self._value(name))
            if not (math.isfinite(value) and value >= 0.0):
                raise ValueError(f'{name} must be a number >= 0, got {value}')
        if self._value('particle_cloud_type') not in ('ParticleCloud', 'PoseArray'):
            raise ValueError(f"particle_cloud_type must be 'ParticleCloud' or 'PoseArray', "
                             f"got '{self._value('particle_cloud_type')}'")

    def on_activate(self, state: State) -> TransitionCallbackReturn:
        self._active = True
        result = super().on_activate(state)
        if self._value('set_initial_pose'):
            pose = np.array([self._value('initial_pose.x'), self._value('initial_pose.y'),
                             self._value('initial_pose.yaw')], dtype=np.float64)
            self.get_logger().info(f'Initial pose from parameters: x={pose[0]:g} y={pose[1]:g} yaw={pose[2]:g}')
            self._pending_pose = (pose, np.diag([0.25, 0.25, (math.pi / 12) ** 2]))
        self._apply_pending_pose()
        return result

    def on_deactivate(self, state: State) -> TransitionCallbackReturn:
        self._active = False
        return super().on_deactivate(state)

    def on_cleanup(self, state: State) -> TransitionCallbackReturn:
        self._destroy_entities()
        return super().on_cleanup(state)

    def on_shutdown(self, state: State) -> TransitionCallbackReturn:
        self._destroy_entities()
        return super().on_shutdown(state)

    def _destroy_entities(self) -> None:
        for entity in reversed(self._entities):
            if not self._destroy_entity(entity):
                entity.destroy()
        self._entities.clear()
        for pub in ('_pose_pub', '_cloud_pub'):
            if hasattr(self, pub):
                self.destroy_lifecycle_publisher(getattr(self, pub))
                delattr(self, pub)
        if hasattr(self, '_tf_listener'):
            self._tf_listener.unregister()
        self._reset_state()

    # -- input -------------------------------------------------------------------------------------
    def _warn_once(self, key: str, text: str) -> None:
        if key not in self._warned:
            self._warned.add(key)
            self.get_logger().warn(text)

    def _on_map(self, msg: Any) -> None:
        if self._amcl is not None and self._value('first_map_only'):
            return
        info = msg.info
        try:
            grid = MapGrid(np.asarray(msg.data), resolution=float(info.resolution),
                           origin=(float(info.origin.position.x), float(info.origin.position.y)),
                           width=int(info.width))
        except ValueError as exc:
            self.get_logger().error(f'Ignoring the map on {self._value("map_topic")}: {exc}')
            return
        if msg.header.frame_id.lstrip('/') not in ('', self._global_frame):
            self._warn_once('map_frame', f"The map is in frame '{msg.header.frame_id}', not global_frame_id "
                                         f"'{self._global_frame}': poses are published in '{self._global_frame}'")
        self.get_logger().info(f'Received a {grid.width} X {grid.height} map @ {grid.resolution:.3f} m/pix')
        if self._amcl is None:
            self._amcl = Amcl(self.parameters, grid)
            return self._apply_pending_pose()
        estimate = self._amcl.estimate
        self._amcl.set_map(grid)
        if self._value('always_reset_initial_pose') or estimate is None:
            self._amcl.pose_known = False
            self._map_to_odom = None
        else:
            self._amcl.set_initial_pose(estimate.pose, estimate.covariance)

    def _on_initial_pose(self, msg: Any) -> None:
        pose = self._pose_in_map(msg)
        if pose is not None:
            self._pending_pose = pose
            if not self._active:
                self.get_logger().info('Received an initial pose while not active: it is used on activation')
            self._apply_pending_pose()

    def _on_set_initial_pose(self, request: Any, response: Any) -> Any:
        self._on_initial_pose(request.pose)
        return response

    def _pose_in_map(self, msg: Any) -> tuple[np.ndarray, np.ndarray] | None:
        """(x, y, yaw) and the 3x3 covariance of an initial pose, in the global frame; None (with
        a warning) for one that cannot be used."""
        p, q, c = msg.pose.pose.position, msg.pose.pose.orientation, np.asarray(msg.pose.covariance, dtype=np.float64)
        values = np.array([p.x, p.y, q.x, q.y, q.z, q.w], dtype=np.float64)
        if not (np.isfinite(values).all() and c.size == 36 and np.isfinite(c).all()):
            self.get_logger().warn('Ignoring an initial pose with NaN or infinite values (or a covariance '
                                   'that is not 36 numbers)')
            return None
        if not (q.x or q.y or q.z or q.w):
            self.get_logger().warn('The initial pose has an all-zero quaternion: read as yaw 0')
        yaw = yaw_from_quaternion(q.x, q.y, q.z, q.w)
        covariance = np.array([[c[0], c[1], 0.0], [c[6], c[7], 0.0], [0.0, 0.0, c[35]]])
        if min(c[0], c[7], c[35]) < 0.0:
            self.get_logger().warn('Ignoring an initial pose with a negative variance')
            return None
        pose = np.array([p.x, p.y, yaw])
        frame = msg.header.frame_id.lstrip('/')
        if frame == '':
            self.get_logger().warn(f"The initial pose has no frame_id: taken as '{self._global_frame}'")
        elif frame != self._global_frame:
            try:
                t = self._tf_buffer.lookup_transform(self._global_frame, frame, Time(), timeout=TF_WAIT)
            except TransformException as exc:
                self.get_logger().warn(f"Ignoring an initial pose in frame '{frame}': initial poses must be in "
                                       f"'{self._global_frame}' or a frame with a transform to it ({exc})")
                return None
            transform = _pose2d(t.transform.translation, t.transform.rotation)
            pose = compose(transform, pose)
            rotation = np.array([[math.cos(transform[2]), -math.sin(transform[2])],
                                 [math.sin(transform[2]), math.cos(transform[2])]])
            covariance[:2, :2] = rotation @ covariance[:2, :2] @ rotation.T
            self.get_logger().info(f"Initial pose given in '{frame}', transformed into '{self._global_frame}'")
        return pose, covariance

    def _apply_pending_pose(self) -> None:
        if not self._active or self._pending_pose is None or self._amcl is None:
            return
        pose, covariance = self._pending_pose
        self._pending_pose = None
        self.get_logger().info(f'Setting pose: x={pose[0]:.3f} y={pose[1]:.3f} yaw={pose[2]:.3f}')
        if not self._amcl.set_initial_pose(pose, covariance):
            self.get_logger().warn('The initial pose is not in the map\'s free space: particles put there anyway')
        self._publish_cloud(self.get_clock().now().to_msg())

    def _on_global_localization(self, request: Any, response: Any) -> Any:
        if self._amcl is None:
            self.get_logger().warn('reinitialize_global_localization: no map yet, nothing to spread particles over')
            return response
        self.get_logger().info('Initializing with uniform distribution')
        self._amcl.global_localization()
        self.get_logger().info(f'Global initialisation done: {len(self._amcl.pf)} particles over the free space')
        self._publish_cloud(self.get_clock().now().to_msg())
        return response

    def _on_nomotion_update(self, request: Any, response: Any) -> Any:
        if self._amcl is not None:
            self._amcl.request_nomotion_update()
            self.get_logger().info('Requesting no-motion update')
        return response

    # -- each scan ---------------------------------------------------------------------------------------
    def _on_scan(self, msg: Any) -> None:
        if not self._active:
            return
        self._last_scan_wall = time.monotonic()
        amcl = self._amcl
        if amcl is None or not amcl.pose_known:
            return                                 # the status timer says why
        ranges = np.asarray(msg.ranges, dtype=np.float64)
        if np.isnan(ranges).any():
            self._warn_once('nan_scan', f"Scans on {self._value('scan_topic')} contain NaN ranges: those beams "
                                        'are ignored (said once)')
        stamp = Time.from_msg(msg.header.stamp)
        laser_pose = self._laser_pose(msg.header.frame_id)
        odom = self._odom_pose(stamp) if laser_pose is not None else None
        if odom is None:
            return
        scan = amcl.prepare_scan(ranges, self._scan_bearings(msg, len(ranges)), float(msg.range_min),
                                 float(msg.range_max))
        result = amcl.update(odom, scan, laser_pose)
        if result.updated:
            self._publish_cloud(msg.header.stamp)
        if result.published:
            self._publish_pose(msg.header.stamp, result.estimate)
            self._map_to_odom = amcl.map_to_odom()
            self._save_pose(result.estimate.pose)
        if self._map_to_odom is not None and self._value('tf_broadcast'):
            self._publish_transform(stamp + self._tolerance)

    def _laser_pose(self, frame: str) -> tuple[float, float, float] | None:
        """The laser's (x, y, 0) in the base frame; its mounting yaw goes into the bearings."""
        if frame not in self._laser_poses:
            try:
                t = self._tf_buffer.lookup_transform(self._base_frame, frame, Time(), timeout=TF_WAIT)
            except TransformException as exc:
                self.get_logger().warn(f"Cannot place the laser: no transform from '{self._base_frame}' to "
                                       f"'{frame}' ({exc})", throttle_duration_sec=NAG_PERIOD)
                return None
            translation, r = t.transform.translation, t.transform.rotation
            self._laser_poses[frame] = ((translation.x, translation.y, 0.0),
                                        quaternion_matrix([r.x, r.y, r.z, r.w])[:3, :3])
        return self._laser_poses[frame][0]

    def _scan_bearings(self, msg: Any, count: int) -> np.ndarray:
        """Beam directions [rad] in the base frame: works for lasers mounted turned or upside down."""
        key = (msg.header.frame_id, float(msg.angle_min), float(msg.angle_increment), count)
        bearings = self._bearings.get(key)
        if bearings is None:
            rotation = self._laser_poses[msg.header.frame_id][1]
            angles = msg.angle_min + msg.angle_increment * np.arange(count)
            directions = np.outer(np.cos(angles), rotation[:, 0]) + np.outer(np.sin(angles), rotation[:, 1])
            bearings = self._bearings[key] = np.arctan2(directions[:, 1], directions[:, 0])
        return bearings

    def _odom_pose(self, stamp: Time) -> tuple[float, float, float] | None:
        """odom -> base at the scan's time (never another time's: the scan would be misplaced)."""
        try:
            t = self._tf_buffer.lookup_transform(self._odom_frame, self._base_frame, stamp, timeout=TF_WAIT)
        except TransformException as exc:
            self.get_logger().warn(f"Dropping a scan: no '{self._odom_frame}' -> '{self._base_frame}' transform "
                                   f'at its time ({exc})', throttle_duration_sec=NAG_PERIOD)
            return None
        return tuple(_pose2d(t.transform.translation, t.transform.rotation))

    # -- output --------------------------------------------------------------------------------------
    def _publish_pose(self, stamp: Any, estimate: Any) -> None:
        msg = PoseWithCovarianceStamped()
        msg.header.stamp, msg.header.frame_id = stamp, self._global_frame
        _fill_pose(msg.pose.pose, estimate.pose)
        covariance = np.zeros(36)
        covariance[[0, 1, 6, 7]] = estimate.covariance[:2, :2].ravel()
        covariance[35] = estimate.covariance[2, 2]
        msg.pose.covariance = covariance
        self._pose_pub.publish(msg)

    def _publish_cloud(self, stamp: Any) -> None:
        """The particles as ParticleCloud (with weights) or PoseArray, after each filter update
        and each (re)initialisation, when someone listens. The message objects are kept and
        refilled: building thousands of fresh ones costs ten times more."""
        if self._cloud_pub.get_subscription_count() == 0:
            return
        pf = self._amcl.pf
        cache = self._cloud_cache
        while len(cache) < len(pf):
            cache.append(Particle() if self._cloud_type is ParticleCloud else Pose())
        items = cache[:len(pf)]
        half = pf.particles[:, 2] / 2.0
        columns = (pf.particles[:, 0].tolist(), pf.particles[:, 1].tolist(), np.sin(half).tolist(),
                   np.cos(half).tolist(), pf.weights.tolist())
        for item, x, y, qz, qw, weight in zip(items, *columns):
            pose = item.pose if self._cloud_type is ParticleCloud else item
            pose.position.x, pose.position.y, pose.orientation.z, pose.orientation.w = x, y, qz, qw
            if pose is not item:
                item.weight = weight
        msg = ParticleCloud(particles=items) if self._cloud_type is ParticleCloud else PoseArray(poses=items)
        msg.header.stamp, msg.header.frame_id = stamp, self._global_frame
        self._cloud_pub.publish(msg)

    def _publish_transform(self, stamp: Time) -> None:
        t = TransformStamped()
        t.header.stamp, t.header.frame_id, t.child_frame_id = stamp.to_msg(), self._global_frame, self._odom_frame
        x, y, yaw = self._map_to_odom
        t.transform.translation.x, t.transform.translation.y = float(x), float(y)
        r = t.transform.rotation
        r.x, r.y, r.z, r.w = quaternion_from_yaw(float(yaw))
        self._tf_broadcaster.sendTransform(t)

    def _save_pose(self, pose: np.ndarray) -> None:
        """Keep the last pose in initial_pose.* (save_pose_rate), as Nav2 does, for a restart."""
        rate = float(self._value('save_pose_rate'))
        now = time.monotonic()
        if rate > 0.0 and now - self._last_save >= 1.0 / rate:
            self._last_save = now
            self.set_parameters([Parameter('initial_pose.x', value=float(pose[0])),
                                 Parameter('initial_pose.y', value=float(pose[1])),
                                 Parameter('initial_pose.yaw', value=float(pose[2]))])

    def _report_status(self) -> None:
        """Say what the node waits for (log every NAG_PERIOD, /diagnostics every STATUS_PERIOD)."""
        level, message = self._status()
        status = DiagnosticStatus(level=level, name='amcl: Localization', message=message, hardware_id='')
        if self._amcl is not None and self._amcl.estimate is not None:
            x, y, yaw = self._amcl.estimate.pose
            status.values = [KeyValue(key='pose', value=f'x={x:.3f} y={y:.3f} yaw={yaw:.3f}'),
                             KeyValue(key='particles', value=str(len(self._amcl.pf)))]
        array = DiagnosticArray(status=[status])
        array.header.stamp = self.get_clock().now().to_msg()
        self._diagnostics_pub.publish(array)
        now = time.monotonic()
        if level != DiagnosticStatus.OK and self._active and now - self._last_nag >= NAG_PERIOD:
            self._last_nag = now
            self.get_logger().warn(message)

    def _status(self) -> tuple[int, str]:
        warn = DiagnosticStatus.WARN
        if not self._active:
            return warn, f"Not active ({self.current_state.label}): activate amcl to localize"
        if self._amcl is None:
            return warn, f"Waiting for the map on '{self._value('map_topic')}' (nothing received yet)"
        if not self._amcl.pose_known:
            return warn, ('No initial pose yet: publish one on /initialpose (RViz\'s 2D Pose Estimate), call '
                          'reinitialize_global_localization, or set set_initial_pose with initial_pose.x/y/yaw. '
                          f"Until then amcl publishes no pose and no {self._global_frame} -> {self._odom_frame} "
                          'transform.')
        if self._last_scan_wall is None or time.monotonic() - self._last_scan_wall > 2 * NAG_PERIOD:
            return warn, f"No scans on '{self._value('scan_topic')}' for a while: the pose is not updated"
        if self._amcl.estimate is None:
            return warn, 'Waiting for odometry to place the first scan'
        return DiagnosticStatus.OK, 'Localizing'


def _pose2d(translation: Any, rotation: Any) -> np.ndarray:
    return np.array([translation.x, translation.y, yaw_from_quaternion(rotation.x, rotation.y, rotation.z, rotation.w)])


def _fill_pose(msg: Any, pose: np.ndarray) -> Any:
    msg.position.x, msg.position.y = float(pose[0]), float(pose[1])
    q = msg.orientation
    q.x, q.y, q.z, q.w = quaternion_from_yaw(float(pose[2]))
    return msg



def main(args: list[str] | None = None) -> None:
    try:
        with zros.init(args=args):
            zros.spin(AmclNode())
    except (KeyboardInterrupt, ExternalShutdownException):
        pass


if __name__ == '__main__':
    main(sys.argv)
