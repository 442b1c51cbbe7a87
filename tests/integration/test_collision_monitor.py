"""nav2_collision_monitor: zone decisions as plain code on synthetic scans (stop, slowdown,
limit, approach, min_points, the slowest wins), then the node as a process between
`cmd_vel_smoothed` and `cmd_vel`, with the scan put in the base frame through TF."""
from __future__ import annotations

import numpy as np
import pytest

from conftest import activate, wait_until
from zros.navigation.collision_monitor import Zone, decide, points_in_polygon, scan_points

SQUARE = np.array([[0.3, 0.3], [0.3, -0.3], [-0.3, -0.3], [-0.3, 0.3]])
CMD = np.array([0.4, 0.0, 0.5])


def _wall_at(x: float, n: int = 30) -> np.ndarray:
    """A scan of a wall across the robot's path at distance x [m] ahead, as base-frame points."""
    ranges = np.full(360, np.inf)
    angles = np.deg2rad(np.arange(360)) - np.pi
    ahead = np.abs(angles) < np.arctan2(0.4, x)
    ranges[ahead] = x / np.cos(angles[ahead])
    points = scan_points(ranges, -np.pi, np.deg2rad(1.0), 0.1, 3.5)
    assert len(points) >= n // 2
    return points


def test_points_in_polygon_and_scan_points():
    inside = points_in_polygon(np.array([[0.0, 0.0], [0.29, -0.29], [0.31, 0.0], [0.0, -0.4]]), SQUARE)
    assert inside.tolist() == [True, True, False, False]
    pts = scan_points(np.array([1.0, np.nan, 0.05, 2.0, 9.0]), 0.0, np.pi / 2, 0.1, 3.5)
    assert pts == pytest.approx(np.array([[1.0, 0.0], [0.0, -2.0]]), abs=1e-12)   # 0 and 270 degrees


def test_stop_and_slowdown_zones_with_a_synthetic_scan():
    zones = [Zone('PolygonStop', 'stop', vertices=SQUARE * [1.0, 1.0]),
             Zone('PolygonSlow', 'slowdown', vertices=SQUARE * [2.0, 2.0], slowdown_ratio=0.3)]
    far = decide(zones, _wall_at(1.5), CMD)
    assert far.action == 'do_nothing' and far.velocity == pytest.approx(CMD)
    slow = decide(zones, _wall_at(0.5), CMD)
    assert (slow.action, slow.polygon_name) == ('slowdown', 'PolygonSlow')
    assert slow.velocity == pytest.approx(CMD * 0.3)
    stop = decide(zones, _wall_at(0.25), CMD)
    assert (stop.action, stop.polygon_name) == ('stop', 'PolygonStop') and not stop.velocity.any()
    wall = _wall_at(0.25)
    few = wall[np.argsort(np.hypot(wall[:, 0], wall[:, 1]))[:3]]   # fewer than min_points (4): ignored
    assert decide(zones, few, CMD).action == 'do_nothing'
    assert decide([Zone('c', 'stop', radius=0.3, min_points=3)], few, CMD).action == 'stop'


def test_limit_and_the_slowest_zone_wins():
    limit = Zone('Limit', 'limit', radius=1.0, linear_limit=0.1, angular_limit=0.2)
    slow = Zone('Slow', 'slowdown', radius=1.0, slowdown_ratio=0.5)
    points = _wall_at(0.6)
    alone = decide([limit], points, CMD)
    assert alone.action == 'limit' and alone.velocity == pytest.approx([0.1, 0.0, 0.125])   # one ratio, 0.25
    both = decide([slow, limit], points, CMD)
    assert both.polygon_name == 'Limit'                          # 0.1 m/s is slower than 0.2 m/s
    assert decide([Zone('off', 'stop', radius=1.0, enabled=False)], points, CMD).action == 'do_nothing'


def test_approach_slows_down_with_the_time_to_collision():
    footprint = Zone('Footprint', 'approach', vertices=SQUARE * [0.5, 0.5], time_before_collision=2.0,
                     simulation_time_step=0.1, min_points=3)
    straight = np.array([0.4, 0.0, 0.0])
    near = decide([footprint], _wall_at(0.55), straight)           # 0.4 m to go at 0.4 m/s: 1 s
    assert near.action == 'approach' and near.velocity[0] == pytest.approx(0.4 * 1.0 / 2.0, abs=0.03)
    nearer = decide([footprint], _wall_at(0.35), straight)
    assert nearer.velocity[0] < near.velocity[0]
    assert decide([footprint], _wall_at(2.0), straight).action == 'do_nothing'   # beyond 2 s
    assert decide([footprint], _wall_at(0.55), -straight).action == 'do_nothing'  # driving away
    with pytest.raises(ValueError, match='action_type'):
        Zone('x', 'swerve', radius=1.0)


PARAMS = '''collision_monitor:
  ros__parameters:
    base_frame_id: base_footprint
    cmd_vel_in_topic: cmd_vel_smoothed
    cmd_vel_out_topic: cmd_vel
    state_topic: collision_monitor_state
    source_timeout: 5.0
    polygons: ["PolygonStop", "PolygonSlow"]
    PolygonStop:
      type: polygon
      points: "[[0.3, 0.3], [0.3, -0.3], [-0.3, -0.3], [-0.3, 0.3]]"
      action_type: stop
      min_points: 4
    PolygonSlow:
      type: circle
      radius: 0.8
      action_type: slowdown
      slowdown_ratio: 0.25
    observation_sources: ["scan"]
    scan:
      type: scan
      topic: /scan
'''


def test_node_stops_and_slows_the_robot_on_the_scan(spawn, probe, tmp_path):
    from zros.tf2_ros import StaticTransformBroadcaster
    from interfaces.geometry_msgs.msg import TransformStamped, Twist
    from interfaces.nav2_msgs.msg import CollisionMonitorState
    from interfaces.sensor_msgs.msg import LaserScan
    params = tmp_path / 'params.yaml'
    params.write_text(PARAMS)
    monitor = spawn.node('nav2_collision_monitor', 'collision_monitor', '--ros-args', '--params-file', params)
    node = probe
    activate(node, 'collision_monitor', monitor)

    # The scanner sits 0.1 m behind base_footprint's origin, turned by pi: a wall "behind" it is ahead.
    static = StaticTransformBroadcaster(node)
    mount = TransformStamped()
    mount.header.frame_id, mount.child_frame_id = 'base_footprint', 'base_scan'
    mount.transform.translation.x = -0.1
    mount.transform.rotation.z, mount.transform.rotation.w = 1.0, 0.0
    static.sendTransform(mount)
    scan_pub = node.create_publisher(LaserScan, '/scan', 5)
    cmd_pub = node.create_publisher(Twist, 'cmd_vel_smoothed', 1)
    out: list = []
    states: list = []
    node.create_subscription(Twist, 'cmd_vel', out.append, 10)
    node.create_subscription(CollisionMonitorState, 'collision_monitor_state', states.append, 10)
    command = Twist()
    command.linear.x, command.angular.z = 0.2, 0.1

    def drive_with_wall_at(distance: float, expected_x: float) -> None:
        ranges = np.full(360, np.inf)
        angles = np.deg2rad(np.arange(360)) - np.pi            # scanner frame; ahead of the robot is +-pi
        behind = np.abs(np.abs(angles) - np.pi) < np.arctan2(0.4, distance + 0.1)
        ranges[behind] = (distance + 0.1) / np.abs(np.cos(angles[behind]))
        scan = LaserScan(angle_min=-np.pi, angle_increment=float(np.deg2rad(1.0)), range_min=0.1, range_max=3.5,
                         ranges=ranges.astype(np.float32))
        scan.header.frame_id = 'base_scan'

        def seen() -> bool:
            scan.header.stamp = node.get_clock().now().to_msg()
            scan_pub.publish(scan)
            cmd_pub.publish(command)
            return bool(out) and abs(out[-1].linear.x - expected_x) < 1e-6
        wait_until(seen, 10, interval=0.1, message=f'cmd_vel.linear.x {expected_x} with a wall {distance} m ahead '
                                                   f'(got {[t.linear.x for t in out[-3:]]})')

    drive_with_wall_at(2.0, 0.2)
    drive_with_wall_at(0.6, 0.05)
    assert out[-1].angular.z == pytest.approx(0.025)
    drive_with_wall_at(0.2, 0.0)
    wait_until(lambda: any(s.action_type == CollisionMonitorState.STOP and s.polygon_name == 'PolygonStop'
                           for s in states), 5, message='the stop reported on state_topic')
    monitor.wait_for_output('Robot to stop due to PolygonStop polygon', timeout=5)


def test_a_bad_polygon_fails_in_one_line(zros_cli, domain, tmp_path):
    from conftest import assert_clean_failure
    params = tmp_path / 'bad.yaml'
    params.write_text(PARAMS.replace('action_type: stop', 'action_type: swerve'))
    result = zros_cli('run', 'nav2_collision_monitor', 'collision_monitor', '--ros-args', '--params-file', params)
    assert_clean_failure(result, 'PolygonStop', 'swerve')
