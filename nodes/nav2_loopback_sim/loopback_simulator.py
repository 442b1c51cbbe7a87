"""nav2_loopback_sim's loopback_simulator: the robot is exactly where its commands say.

    zros run nav2_loopback_sim loopback_simulator --ros-args --params-file nav2_params.yaml
    zros launch nav2_loopback_sim loopback_simulation.launch.py

Nav2 Jazzy's stand-in for a physics simulator *and* for localization, for testing planners,
behaviour trees and missions without Gazebo's or AMCL's cost and noise. It integrates `cmd_vel`
(geometry_msgs/Twist, or TwistStamped with `enable_stamped_cmd_vel`) with no dynamics into
`odom_frame_id -> base_frame_id` (TF and `odom`), publishes `map_frame_id -> odom_frame_id` from
`initialpose` (with `publish_map_odom_tf`), ray-casts a `scan` in `scan_frame_id` from the map
server's map (`/map_server/map`, nav_msgs/GetMap) so the collision monitor and obstacle layers
are fed, and publishes `/clock` (`publish_clock`) from the wall clock, for the rest of the
stack's `use_sim_time`.

Nothing moves before the first `initialpose`: until then only an identity odom -> base is sent
(the stack can come up), and commands are dropped. The first initial pose is map -> odom; a later
one moves the robot there by changing map -> odom, keeping odometry continuous. A command older
than 1 s stops the robot. The scan needs base -> `scan_frame_id` from TF (robot_state_publisher)
and the map; without either its beams are all out of range, as upstream's.

Parameters (Nav2's names and defaults): `update_duration` (0.01 s), `base_frame_id`
("base_footprint"), `odom_frame_id` ("odom"), `map_frame_id` ("map"), `scan_frame_id`
("base_scan"), `enable_stamped_cmd_vel` (false), `scan_publish_dur` (0.1 s),
`publish_map_odom_tf` (true), `publish_clock` (true), `scan_range_min` (0.05 m),
`scan_range_max` (30 m), `scan_angle_min` (-pi), `scan_angle_max` (pi), `scan_angle_increment`
(0.0261 rad), `scan_use_inf` (true; false reports `scan_range_max - 0.1` for no return).
"""
from __future__ import annotations

import contextlib
import math
import sys
from typing import Any

import numpy as np

import zros
from zros.clock import Clock
from zros.duration import Duration
from zros.executors import ExternalShutdownException
from zros.grid_geometry import GridGeometry
from zros.navigation.node_support import quaternion_of, yaw_of
from zros.node import Node
from zros.qos import qos_profile_sensor_data
from zros.sim.grid_lidar import GridLidar
from zros.sim.robot import integrate_twist
from zros.slam.geometry import compose, inverse
from zros.tf2_ros import Buffer, TransformBroadcaster, TransformListener
from zros.time import Time

from interfaces.geometry_msgs.msg import PoseWithCovarianceStamped, TransformStamped, Twist, TwistStamped
from interfaces.nav_msgs.msg import Odometry
from interfaces.nav_msgs.srv import GetMap
from interfaces.rosgraph_msgs.msg import Clock as ClockMsg
from interfaces.sensor_msgs.msg import LaserScan

__all__ = ['LoopbackSimulator', 'main']

#: [s] a command older than this is no longer followed (upstream's one second).
COMMAND_TIMEOUT_S = 1.0
#: [s] between /clock messages, and between tries for the map and base -> scan before the start.
_TICK_S = 0.1

_PARAMETERS = (('update_duration', 0.01), ('base_frame_id', 'base_footprint'), ('odom_frame_id', 'odom'),
               ('map_frame_id', 'map'), ('scan_frame_id', 'base_scan'), ('enable_stamped_cmd_vel', False),
               ('scan_publish_dur', 0.1), ('publish_map_odom_tf', True), ('publish_clock', True),
               ('scan_range_min', 0.05), ('scan_range_max', 30.0), ('scan_angle_min', -math.pi),
               ('scan_angle_max', math.pi), ('scan_angle_increment', 0.0261), ('scan_use_inf', True))


def _check(p: dict[str, Any]) -> str | None:
    """Why the parameters cannot run, or None."""
    for name in ('update_duration', 'scan_publish_dur', 'scan_angle_increment', 'scan_range_max'):
        if not (math.isfinite(p[name]) and p[name] > 0):
            return f'{name} must be > 0, got {p[name]}'
    if not p['scan_angle_max'] > p['scan_angle_min']:
        return f'scan_angle_max ({p["scan_angle_max"]}) must be above scan_angle_min ({p["scan_angle_min"]})'
    return None


class LoopbackSimulator(Node):
    """cmd_vel in, odometry, TF, scan and clock out (module docstring)."""

    def __init__(self, **kwargs: Any) -> None:
        super().__init__('loopback_simulator', **kwargs)
        p = {name: self.declare_parameter(name, default).value for name, default in _PARAMETERS}
        p = {name: float(value) if isinstance(value, int) and not isinstance(value, bool) else value
             for name, value in p.items()}
        problem = _check(p)
        if problem:
            raise ValueError(problem)
        self.p = p
        self.map_to_odom: tuple[float, float, float] | None = None     # None until the first initialpose
        self.odom_to_base = (0.0, 0.0, 0.0)
        self.command: tuple[float, float, float] | None = None
        self.command_time = self.get_clock().now()
        self.base_to_scan: tuple[float, float, float] | None = None
        self.lidar: GridLidar | None = None
        self._map_request: Any = None
        self.broadcaster = TransformBroadcaster(self)
        self.tf_buffer = Buffer()
        self.tf_listener = TransformListener(self.tf_buffer, self)
        self.create_subscription(PoseWithCovarianceStamped, 'initialpose', self._on_initial_pose, 10)
        if p['enable_stamped_cmd_vel']:
            self.create_subscription(TwistStamped, 'cmd_vel', self._on_stamped_command, 10)
        else:
            self.create_subscription(Twist, 'cmd_vel', self._on_command, 10)
        self.odom_pub = self.create_publisher(Odometry, 'odom', 10)
        self.scan_pub = self.create_publisher(LaserScan, 'scan', qos_profile_sensor_data)
        if p['publish_clock']:
            # The stack runs on this clock; it cannot also follow it.
            self.wall = Clock()
            self.clock_pub = self.create_publisher(ClockMsg, '/clock', 10)
            self.create_timer(_TICK_S, self._publish_clock)
        self.map_client = self.create_client(GetMap, '/map_server/map')
        self._setup = self.create_timer(_TICK_S, self._before_start)
        self._update: Any = None
        self.get_logger().info('Loopback simulator initialized: waiting for an initial pose on initialpose')

    # -- inputs ---------------------------------------------------------------------------------
    def _on_command(self, msg: Any) -> None:
        self._command(msg, self.get_clock().now())

    def _on_stamped_command(self, msg: Any) -> None:
        self._command(msg.twist, Time.from_msg(msg.header.stamp))

    def _command(self, twist: Any, stamp: Any) -> None:
        if self.map_to_odom is None:
            return                       # nothing moves before the robot has been placed
        self.command = (twist.linear.x, twist.linear.y, twist.angular.z)
        self.command_time = stamp

    def _on_initial_pose(self, msg: Any) -> None:
        pose = msg.pose.pose
        map_to_base = np.array([pose.position.x, pose.position.y, yaw_of(pose.orientation)])
        self.get_logger().info(f'Initial pose: ({map_to_base[0]:.2f}, {map_to_base[1]:.2f}, '
                               f'{map_to_base[2]:.2f} rad)')
        first = self.map_to_odom is None
        if first:
            self.odom_to_base = (0.0, 0.0, 0.0)
        self.map_to_odom = tuple(compose(map_to_base, inverse(np.array(self.odom_to_base))).tolist())
        if first:
            self._update = self.create_timer(self.p['update_duration'], self._step)
            self.create_timer(self.p['scan_publish_dur'], self._publish_scan)
        self._publish_transforms()

    # -- timers ---------------------------------------------------------------------------------
    def _before_start(self) -> None:
        """Until the robot is placed: an identity odom -> base (so the stack can configure); until
        the scan can be made: the map and base -> scan."""
        if self.map_to_odom is None:
            self._send(self.p['odom_frame_id'], self.p['base_frame_id'], self.odom_to_base,
                       self.get_clock().now())
        self._fetch_map()
        self._fetch_scan_mount()
        if self.lidar is not None and self.base_to_scan is not None and self.map_to_odom is not None:
            self.destroy_timer(self._setup)

    def _fetch_map(self) -> None:
        if self.lidar is not None:
            return
        if self._map_request is None:
            if self.map_client.service_is_ready():
                self._map_request = self.map_client.call_async(GetMap.Request())
            return
        if not self._map_request.done():
            return
        answer, self._map_request = self._map_request.result(), None
        if answer is None:
            return
        info = answer.map.info
        geometry = GridGeometry(info.resolution, (info.origin.position.x, info.origin.position.y,
                                                  yaw_of(info.origin.orientation)), (info.height, info.width))
        occupancy = np.asarray(answer.map.data, dtype=np.int8).reshape(info.height, info.width)
        self.lidar = GridLidar(occupancy, geometry)
        self.get_logger().info(f'Laser scan will be populated using map data ({info.width} x {info.height}, '
                               f'{len(self.lidar.edges)} wall segments)')

    def _fetch_scan_mount(self) -> None:
        if self.base_to_scan is not None:
            return
        try:
            t = self.tf_buffer.lookup_transform(self.p['base_frame_id'], self.p['scan_frame_id'], Time()).transform
        except Exception:  # noqa: BLE001 - tf2's exceptions all mean "not yet": asked again next tick
            return
        self.base_to_scan = (t.translation.x, t.translation.y, yaw_of(t.rotation))

    def _step(self) -> None:
        now = self.get_clock().now()
        if self.command is not None and now - self.command_time > Duration(seconds=COMMAND_TIMEOUT_S):
            self.command = None
        if self.command is not None:
            self.odom_to_base = integrate_twist(self.odom_to_base, self.command, self.p['update_duration'])
            self._publish_odometry(now)
        self._publish_transforms()

    def _publish_clock(self) -> None:
        self.clock_pub.publish(ClockMsg(clock=self.wall.now().to_msg()))

    # -- outputs --------------------------------------------------------------------------------
    def _send(self, parent: str, child: str, pose: tuple[float, float, float], stamp: Any) -> None:
        t = TransformStamped()
        t.header.frame_id, t.header.stamp, t.child_frame_id = parent, stamp.to_msg(), child
        t.transform.translation.x, t.transform.translation.y = float(pose[0]), float(pose[1])
        quaternion_of(float(pose[2]), t.transform.rotation)
        self.broadcaster.sendTransform(t)

    def _publish_transforms(self) -> None:
        now = self.get_clock().now()
        if self.p['publish_map_odom_tf']:
            # Dated one step ahead, as upstream's, so lookups at "now" never extrapolate.
            self._send(self.p['map_frame_id'], self.p['odom_frame_id'], self.map_to_odom,
                       now + Duration(seconds=self.p['update_duration']))
        self._send(self.p['odom_frame_id'], self.p['base_frame_id'], self.odom_to_base, now)

    def _publish_odometry(self, now: Any) -> None:
        odom = Odometry()
        odom.header.stamp, odom.header.frame_id = now.to_msg(), self.p['odom_frame_id']
        odom.child_frame_id = self.p['base_frame_id']
        odom.pose.pose.position.x, odom.pose.pose.position.y = self.odom_to_base[0], self.odom_to_base[1]
        quaternion_of(self.odom_to_base[2], odom.pose.pose.orientation)
        odom.twist.twist.linear.x, odom.twist.twist.linear.y, odom.twist.twist.angular.z = self.command
        self.odom_pub.publish(odom)

    def _publish_scan(self) -> None:
        p = self.p
        count = int((p['scan_angle_max'] - p['scan_angle_min']) / p['scan_angle_increment'])
        scan = LaserScan()
        scan.header.stamp, scan.header.frame_id = self.get_clock().now().to_msg(), p['scan_frame_id']
        scan.angle_min, scan.angle_max = p['scan_angle_min'], p['scan_angle_max']
        scan.angle_increment, scan.scan_time = p['scan_angle_increment'], p['scan_publish_dur']
        scan.range_min, scan.range_max = p['scan_range_min'], p['scan_range_max']
        if self.lidar is None or self.base_to_scan is None or self.map_to_odom is None:
            ranges = np.full(count, math.inf)
        else:
            sensor = compose(compose(np.array(self.map_to_odom), np.array(self.odom_to_base)),
                             np.array(self.base_to_scan))
            ranges = self.lidar.scan(sensor, p['scan_angle_min'], p['scan_angle_increment'], count,
                                     p['scan_range_max'])
        if not p['scan_use_inf']:
            ranges[np.isinf(ranges)] = p['scan_range_max'] - 0.1
        scan.ranges = ranges.astype(np.float32)
        self.scan_pub.publish(scan)


def main(args: list[str] | None = None) -> int:
    with zros.init(args=args):
        try:
            node = LoopbackSimulator()
        except ValueError as exc:                  # a bad parameter: one line, exit 1
            print(f'loopback_simulator: {exc}', file=sys.stderr)
            return 1
        with contextlib.suppress(KeyboardInterrupt, ExternalShutdownException):
            zros.spin(node)
    return 0


if __name__ == '__main__':
    sys.exit(main())
