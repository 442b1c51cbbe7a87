"""nav2_collision_monitor's collision_monitor: the last check of every velocity command against
the laser, in zones around the robot.

    zros run nav2_collision_monitor collision_monitor --ros-args --params-file nav2_params.yaml

Subscribes `cmd_vel_in_topic` (`cmd_vel_smoothed`, what Jazzy's velocity_smoother publishes) and
publishes the allowed command on `cmd_vel_out_topic` (`cmd_vel`); with `state_topic` set, also
which zone acted (nav2_msgs/CollisionMonitorState). A lifecycle node: commands pass only while
it is active. The decisions are zros.navigation.collision_monitor's.

Parameters as Nav2's: `base_frame_id`, `odom_frame_id`, `transform_tolerance`, `source_timeout`,
`stop_pub_timeout` (zero commands are sent for this long after a stop, then nothing),
`polygons` and per polygon `type` (`polygon` with `points` — Jazzy's "[[x, y], ...]" string or
Humble's flat list — or `footprint_topic`, or `circle` with `radius`), `action_type` (stop,
slowdown, limit, approach), `min_points` (Humble's `max_points` + 1), `slowdown_ratio`,
`linear_limit`, `angular_limit`, `time_before_collision`, `simulation_time_step`, `enabled`;
`observation_sources` and per source `type` (`scan`; other types are skipped, said so), `topic`,
`enabled`, `source_timeout`. Scans are put in `base_frame_id` through TF at their latest
transform (`base_shift_correction`, `min_height`, `max_height`, `visualize` are read and
unused). A source with no fresh scan (older than `source_timeout`, 0 = never too old) or no
transform stops the robot, as Jazzy's does.
"""
from __future__ import annotations

import ast
import sys
from typing import Any

import numpy as np

import zros
from zros.executors import ExternalShutdownException
from zros.lifecycle import LifecycleNode, State, TransitionCallbackReturn
from zros.navigation.collision_monitor import ACTIONS, ZONE_PARAMETERS, Decision, Zone, decide, scan_points
from zros.navigation.node_support import Nav2Params, lookup_pose
from zros.navigation.velocity_smoother import twist_vector
from zros.tf2_ros import Buffer, TransformListener
from zros.qos import qos_profile_sensor_data

from interfaces.geometry_msgs.msg import PolygonStamped, Twist
from interfaces.nav2_msgs.msg import CollisionMonitorState
from interfaces.sensor_msgs.msg import LaserScan


class _Source:
    """One observation source: its latest scan and how old it may be."""

    def __init__(self, name: str, topic: str, timeout: float) -> None:
        self.name, self.topic, self.timeout = name, topic, timeout
        self.scan: Any = None

    def on_scan(self, msg: Any) -> None:
        self.scan = msg


class CollisionMonitor(LifecycleNode):
    def __init__(self) -> None:
        super().__init__('collision_monitor')
        self.tf_buffer = Buffer(node=self)
        self.tf_listener = TransformListener(self.tf_buffer, self)
        prm = Nav2Params(self)
        self.base_frame = prm.get('base_frame_id', 'base_footprint')
        prm.get('odom_frame_id', 'odom')
        prm.get('transform_tolerance', 0.1)
        prm.get('base_shift_correction', True)
        source_timeout = prm.get('source_timeout', 2.0)
        self.stop_pub_timeout = prm.get('stop_pub_timeout', 1.0)
        cmd_in = prm.get('cmd_vel_in_topic', 'cmd_vel_smoothed')
        cmd_out = prm.get('cmd_vel_out_topic', 'cmd_vel')
        state_topic = prm.get('state_topic', '')
        self.zones = [self._zone(prm, name) for name in prm.get('polygons', [])]
        self.sources = [s for s in (self._source(prm, name, source_timeout)
                                    for name in prm.get('observation_sources', [])) if s is not None]
        prm.report_unused()
        self.decision = Decision('do_nothing', '', np.zeros(3))
        self._zero_since: float | None = None
        self.cmd_pub = self.create_lifecycle_publisher(Twist, cmd_out, 1)
        self.state_pub = self.create_lifecycle_publisher(CollisionMonitorState, state_topic, 1) if state_topic else None
        self.create_subscription(Twist, cmd_in, self._on_command, 1)

    # -- configuration -----------------------------------------------------------------------
    def _zone(self, prm: Nav2Params, name: str) -> Zone:
        kind = prm.get(f'{name}.type', 'polygon')
        action = prm.get(f'{name}.action_type', 'stop')
        for unused in ('visualize', 'polygon_pub_topic', 'polygon_sub_topic'):
            prm.get(f'{name}.{unused}', '')
        kwargs: dict[str, Any] = {}
        for key in ZONE_PARAMETERS:
            default = getattr(Zone, key)
            kwargs[key] = prm.get(f'{name}.{key}', default)
        if f'{name}.max_points' in self._parameter_overrides and f'{name}.min_points' not in self._parameter_overrides:
            kwargs['min_points'] = prm.get(f'{name}.max_points', 3) + 1
        if kind == 'circle':
            return Zone(name, action, radius=prm.get(f'{name}.radius', 0.3), **kwargs)
        if kind != 'polygon':
            raise ValueError(f'{name}: unknown type {kind!r} (polygon or circle)')
        footprint_topic = prm.get(f'{name}.footprint_topic', '')
        vertices = _vertices(prm.get(f'{name}.points', []), name)
        if vertices is None and not footprint_topic:
            raise ValueError(f'{name}: a polygon needs points or footprint_topic')
        zone = Zone(name, action, vertices=vertices, **kwargs)
        if vertices is None:
            self.create_subscription(PolygonStamped, footprint_topic, lambda msg: self._on_footprint(zone, msg), 1)
        return zone

    def _source(self, prm: Nav2Params, name: str, default_timeout: float) -> _Source | None:
        kind = prm.get(f'{name}.type', 'scan')
        topic = prm.get(f'{name}.topic', 'scan')
        enabled = prm.get(f'{name}.enabled', True)
        timeout = prm.get(f'{name}.source_timeout', default_timeout)
        for unused in ('min_height', 'max_height', 'transform_tolerance'):
            prm.get(f'{name}.{unused}', 0.0)
        if kind != 'scan':
            self.get_logger().warn(f'{name}: observation source type {kind} is not implemented in zros; skipped')
            return None
        if not enabled:
            return None
        source = _Source(name, topic, timeout)
        self.create_subscription(LaserScan, topic, source.on_scan, qos_profile_sensor_data)   # as Nav2's sources
        return source

    def on_activate(self, state: State) -> TransitionCallbackReturn:
        self._zero_since = None
        return super().on_activate(state)

    # -- inputs ------------------------------------------------------------------------------
    def _on_footprint(self, zone: Zone, msg: Any) -> None:
        points = np.array([[p.x, p.y] for p in msg.polygon.points], np.float64).reshape(-1, 2)
        frame = msg.header.frame_id or self.base_frame
        if frame != self.base_frame:
            try:
                points = _moved(points, lookup_pose(self.tf_buffer, self.base_frame, frame))
            except Exception as exc:  # noqa: BLE001 - tf2's exceptions
                self.get_logger().warn(f'{zone.name}: no transform {frame} -> {self.base_frame} for the footprint: '
                                       f'{exc}', throttle_duration_sec=5.0)
                return
        if len(points) >= 3:
            zone.vertices = points

    def _obstacles(self, now: float) -> np.ndarray | None:
        """Every source's points in the base frame [m], or None if a source is stale or untransformable."""
        gathered = [np.zeros((0, 2))]
        for source in self.sources:
            scan = source.scan
            if scan is None:
                self.get_logger().warn(f'{source.name}: no scan on {source.topic} yet: stopping the robot',
                                       throttle_duration_sec=5.0)
                return None
            age = now - (scan.header.stamp.sec + scan.header.stamp.nanosec / 1e9)
            if source.timeout > 0.0 and age > source.timeout:
                self.get_logger().warn(f'{source.name}: the latest scan is {age:.2f} s old (source_timeout '
                                       f'{source.timeout} s): stopping the robot', throttle_duration_sec=5.0)
                return None
            try:
                pose = lookup_pose(self.tf_buffer, self.base_frame, scan.header.frame_id)
            except Exception as exc:  # noqa: BLE001 - tf2's exceptions
                self.get_logger().warn(f'{source.name}: no transform {scan.header.frame_id} -> {self.base_frame}: '
                                       f'{exc}', throttle_duration_sec=5.0)
                return None
            points = scan_points(scan.ranges, scan.angle_min, scan.angle_increment, scan.range_min, scan.range_max)
            gathered.append(_moved(points, pose))
        return np.concatenate(gathered)

    def _on_command(self, msg: Any) -> None:
        if self.current_state.label != 'active':
            return
        now = self.get_clock().now().nanoseconds / 1e9
        command = twist_vector(msg)
        points = self._obstacles(now)
        if points is None:
            decision = Decision('stop', 'invalid source', np.zeros(3))
        else:
            decision = decide(self.zones, points, command)
        if (decision.action, decision.polygon_name) != (self.decision.action, self.decision.polygon_name):
            self._report(decision)
        self.decision = decision
        self._publish(decision.velocity, now)

    # -- outputs -----------------------------------------------------------------------------
    def _report(self, decision: Decision) -> None:
        texts = {'stop': f'Robot to stop due to {decision.polygon_name} polygon',
                 'slowdown': f'Robot to slowdown due to {decision.polygon_name} polygon',
                 'limit': f'Robot to limit speed due to {decision.polygon_name} polygon',
                 'approach': f'Robot to approach due to {decision.polygon_name} polygon',
                 'do_nothing': 'Robot to continue normal operation'}
        self.get_logger().info(texts[decision.action])
        if self.state_pub is not None:
            self.state_pub.publish(CollisionMonitorState(action_type=ACTIONS[decision.action],
                                                         polygon_name=decision.polygon_name))

    def _publish(self, velocity: np.ndarray, now: float) -> None:
        """Send the command; zeros only for `stop_pub_timeout` s after the robot was stopped."""
        if velocity.any():
            self._zero_since = None
        else:
            if self._zero_since is None:
                self._zero_since = now
            if now - self._zero_since > self.stop_pub_timeout:
                return
        twist = Twist()
        twist.linear.x, twist.linear.y, twist.angular.z = (float(v) for v in velocity)
        self.cmd_pub.publish(twist)


def _vertices(value: Any, name: str) -> np.ndarray | None:
    """Polygon vertices (K, 2) from Jazzy's "[[x, y], ...]" string or Humble's flat [x1, y1, ...]."""
    if isinstance(value, str):
        if not value.strip():
            return None
        try:
            value = ast.literal_eval(value)
        except (ValueError, SyntaxError):
            raise ValueError(f'{name}.points: cannot read {value!r} as [[x, y], ...]') from None
    if not value:
        return None
    flat = np.asarray(value, np.float64).ravel()
    if len(flat) % 2:
        raise ValueError(f'{name}.points: an odd number of coordinates ({len(flat)})')
    return flat.reshape(-1, 2)


def _moved(points: np.ndarray, pose: tuple[float, float, float]) -> np.ndarray:
    """(N, 2) points of a frame whose origin is at `pose` (x, y, yaw) in the target frame, in the target frame."""
    x, y, yaw = pose
    c, s = np.cos(yaw), np.sin(yaw)
    return np.stack([x + c * points[:, 0] - s * points[:, 1], y + s * points[:, 0] + c * points[:, 1]], axis=1)


def main(args: list[str] | None = None) -> int:
    try:
        with zros.init(args=args):
            node = CollisionMonitor()
            zros.spin(node)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    except ValueError as exc:
        print(f'collision_monitor: {exc}', file=sys.stderr)
        return 1
    return 0


if __name__ == '__main__':
    sys.exit(main())
