"""fake_robot: a synthetic robot world for the scene view (`zros run zros_view fake_robot`).

Publishes what a TurtleBot3 navigation stack shows in RViz, without a simulator: a 384 x 384
map (0.05 m cells, origin (-10, -10), walls and pillars like turtlebot3_world), TF
map -> odom -> base_footprint -> base_link -> base_scan at 30 Hz, /odom, a 360-beam /scan at
5 Hz ray-cast in the map, 2000 AMCL-like particles on /particle_cloud, /amcl_pose with its
covariance, a /plan to a goal and frontier markers. The view's tests and benchmark use it.

Parameters: x, y, yaw (start pose [m, rad]), speed (m/s along a circle of `radius` [m] round the
start; 0 = stand still), particles (2000), map_rate (Hz, 0 = publish once, latched), scan_rate
(5), tf_rate (30), map_to_odom_x (0.0: the odom frame's offset in the map [m]).
"""
from __future__ import annotations

import math
import sys

import numpy as np

import zros
from zros.executors import ExternalShutdownException, spin_nodes
from zros.grid_geometry import GridGeometry
from zros.node import Node
from zros.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from zros.rotations import quaternion_from_yaw
from zros.sim.grid_lidar import GridLidar

__all__ = ['FakeRobot', 'world_grid', 'cast_scan', 'main']

RESOLUTION, SIZE, ORIGIN = 0.05, 384, -10.0
SCAN_Z = 0.172            # base_link -> base_scan [m]
SCAN_X = -0.032


def world_grid() -> np.ndarray:
    """(SIZE, SIZE) int8 occupancy of the fake world: 0 free inside a 6 x 5 m room with 9
    pillars, 100 on walls and pillars, -1 unknown outside."""
    ys, xs = np.mgrid[0:SIZE, 0:SIZE]
    x = ORIGIN + (xs + 0.5) * RESOLUTION
    y = ORIGIN + (ys + 0.5) * RESOLUTION
    grid = np.full((SIZE, SIZE), -1, dtype=np.int8)
    inside = (np.abs(x) <= 3.0) & (np.abs(y) <= 2.5)
    grid[inside] = 0
    wall = inside & ((np.abs(x) >= 2.85) | (np.abs(y) >= 2.35))
    grid[wall] = 100
    for px in (-1.1, 0.0, 1.1):
        for py in (-1.1, 0.0, 1.1):
            grid[(x - px) ** 2 + (y - py) ** 2 <= 0.15 ** 2] = 100
    return grid


def cast_scan(grid: np.ndarray, x: float, y: float, yaw: float, beams: int = 360, range_max: float = 3.5,
              range_min: float = 0.12) -> np.ndarray:
    """(beams,) float32 ranges [m] from (x, y) at heading `yaw`, beam i at angle i * 2pi/beams,
    inf where nothing is hit between range_min and range_max (zros.sim's GridLidar: the
    simulator's ray caster against the grid's walls)."""
    lidar = GridLidar(grid, GridGeometry(RESOLUTION, (ORIGIN, ORIGIN), grid.shape))
    ranges = lidar.scan((x, y, yaw), 0.0, 2 * math.pi / beams, beams, range_max)
    ranges[ranges < range_min] = np.inf
    return ranges.astype(np.float32)


class FakeRobot(Node):

    def __init__(self) -> None:
        super().__init__('fake_robot')
        from interfaces.geometry_msgs.msg import PoseArray, PoseWithCovarianceStamped
        from interfaces.nav_msgs.msg import OccupancyGrid, Odometry, Path
        from interfaces.sensor_msgs.msg import LaserScan
        from interfaces.tf2_msgs.msg import TFMessage
        from interfaces.visualization_msgs.msg import MarkerArray
        p = {name: self.declare_parameter(name, default).value for name, default in (
            ('x', -1.6), ('y', -0.5), ('yaw', 0.0), ('speed', 0.15), ('radius', 0.45), ('particles', 2000),
            ('map_rate', 0.0), ('scan_rate', 5.0), ('tf_rate', 30.0), ('map_to_odom_x', 0.0))}
        self.p = p
        self.grid = world_grid()
        self.rng = np.random.default_rng(1)
        latched = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                             durability=DurabilityPolicy.TRANSIENT_LOCAL)
        self.map_pub = self.create_publisher(OccupancyGrid, '/map', latched)
        self.tf_pub = self.create_publisher(TFMessage, '/tf', 100)
        self.static_pub = self.create_publisher(TFMessage, '/tf_static', QoSProfile(
            depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL))
        self.odom_pub = self.create_publisher(Odometry, '/odom', 10)
        self.scan_pub = self.create_publisher(LaserScan, '/scan', 10)
        self.cloud_pub = self.create_publisher(PoseArray, '/particle_cloud', 10)
        self.amcl_pub = self.create_publisher(PoseWithCovarianceStamped, '/amcl_pose', latched)
        self.plan_pub = self.create_publisher(Path, '/plan', 10)
        self.marker_pub = self.create_publisher(MarkerArray, '/explore/frontiers', 10)
        self.start = self.get_clock().now()
        self.publish_map()
        self.publish_static()
        if p['map_rate'] > 0:
            self.create_timer(1.0 / p['map_rate'], self.publish_map)
        self.create_timer(1.0 / p['tf_rate'], self.publish_tf)
        self.create_timer(1.0 / p['scan_rate'], self.publish_scan)
        self.create_timer(0.2, self.publish_particles)
        self.create_timer(1.0, self.publish_plan)
        self.get_logger().info('fake robot: /map /tf /odom /scan /particle_cloud /amcl_pose /plan '
                               '/explore/frontiers')

    def pose(self) -> tuple[float, float, float, float]:
        """x, y, yaw of base_footprint in the map, and the time [s] since start."""
        t = (self.get_clock().now() - self.start).nanoseconds * 1e-9
        p = self.p
        if p['speed'] == 0:
            return p['x'], p['y'], p['yaw'], t
        w = p['speed'] / p['radius']
        angle = w * t
        cx, cy = p['x'], p['y'] + p['radius']
        return (cx + p['radius'] * math.sin(angle), cy - p['radius'] * math.cos(angle), p['yaw'] + angle, t)

    def _header(self, msg, frame: str) -> None:
        msg.header.frame_id = frame
        msg.header.stamp = self.get_clock().now().to_msg()

    def publish_map(self) -> None:
        from interfaces.nav_msgs.msg import OccupancyGrid
        msg = OccupancyGrid()
        self._header(msg, 'map')
        msg.info.resolution = RESOLUTION
        msg.info.width = msg.info.height = SIZE
        msg.info.origin.position.x = msg.info.origin.position.y = ORIGIN
        msg.info.origin.orientation.w = 1.0
        msg.data = self.grid.reshape(-1)
        self.map_pub.publish(msg)

    def _transform(self, parent: str, child: str, x: float, y: float, z: float, yaw: float):
        from interfaces.geometry_msgs.msg import TransformStamped
        t = TransformStamped()
        self._header(t, parent)
        t.child_frame_id = child
        t.transform.translation.x, t.transform.translation.y, t.transform.translation.z = x, y, z
        r = t.transform.rotation
        r.x, r.y, r.z, r.w = quaternion_from_yaw(yaw)
        return t

    def publish_static(self) -> None:
        from interfaces.tf2_msgs.msg import TFMessage
        self.static_pub.publish(TFMessage(transforms=[
            self._transform('base_footprint', 'base_link', 0.0, 0.0, 0.010, 0.0),
            self._transform('base_link', 'base_scan', SCAN_X, 0.0, SCAN_Z, 0.0)]))

    def publish_tf(self) -> None:
        from interfaces.nav_msgs.msg import Odometry
        from interfaces.tf2_msgs.msg import TFMessage
        x, y, yaw, _ = self.pose()
        offset = float(self.p['map_to_odom_x'])
        self.tf_pub.publish(TFMessage(transforms=[
            self._transform('map', 'odom', offset, 0.0, 0.0, 0.0),
            self._transform('odom', 'base_footprint', x - offset, y, 0.0, yaw)]))
        odom = Odometry()
        self._header(odom, 'odom')
        odom.child_frame_id = 'base_footprint'
        odom.pose.pose.position.x, odom.pose.pose.position.y = x - offset, y
        q = odom.pose.pose.orientation
        q.x, q.y, q.z, q.w = quaternion_from_yaw(yaw)
        odom.twist.twist.linear.x = float(self.p['speed'])
        self.odom_pub.publish(odom)

    def publish_scan(self) -> None:
        from interfaces.sensor_msgs.msg import LaserScan
        x, y, yaw, _ = self.pose()
        sx, sy = x + SCAN_X * math.cos(yaw), y + SCAN_X * math.sin(yaw)
        scan = LaserScan()
        self._header(scan, 'base_scan')
        scan.angle_min, scan.angle_increment = 0.0, 2 * math.pi / 360
        scan.angle_max = scan.angle_increment * 359
        scan.range_min, scan.range_max = 0.12, 3.5
        scan.scan_time = 1.0 / float(self.p['scan_rate'])
        scan.ranges = cast_scan(self.grid, sx, sy, yaw)
        self.scan_pub.publish(scan)

    def publish_particles(self) -> None:
        from interfaces.geometry_msgs.msg import Pose, PoseArray, PoseWithCovarianceStamped
        x, y, yaw, _ = self.pose()
        n = int(self.p['particles'])
        xs = x + self.rng.normal(0, 0.15, n)
        ys = y + self.rng.normal(0, 0.15, n)
        yaws = yaw + self.rng.normal(0, 0.2, n)
        cloud = PoseArray()
        self._header(cloud, 'map')
        poses = []
        for px, py, pyaw in zip(xs.tolist(), ys.tolist(), yaws.tolist()):
            pose = Pose()
            pose.position.x, pose.position.y = px, py
            q = pose.orientation
            q.x, q.y, q.z, q.w = quaternion_from_yaw(pyaw)
            poses.append(pose)
        cloud.poses = poses
        self.cloud_pub.publish(cloud)
        amcl = PoseWithCovarianceStamped()
        self._header(amcl, 'map')
        amcl.pose.pose.position.x, amcl.pose.pose.position.y = x, y
        q = amcl.pose.pose.orientation
        q.x, q.y, q.z, q.w = quaternion_from_yaw(yaw)
        covariance = np.zeros(36)
        covariance[0], covariance[1], covariance[6], covariance[7], covariance[35] = 0.04, 0.01, 0.01, 0.02, 0.03
        amcl.pose.covariance = covariance
        self.amcl_pub.publish(amcl)

    def publish_plan(self) -> None:
        from interfaces.geometry_msgs.msg import PoseStamped
        from interfaces.nav_msgs.msg import Path
        from interfaces.visualization_msgs.msg import Marker, MarkerArray
        x, y, _, _ = self.pose()
        goal = (2.2, 1.8)
        path = Path()
        self._header(path, 'map')
        poses = []
        for t in np.linspace(0.0, 1.0, 60):
            pose = PoseStamped()
            pose.header = path.header
            pose.pose.position.x = x + (goal[0] - x) * t
            pose.pose.position.y = y + (goal[1] - y) * t + 0.4 * math.sin(math.pi * t)
            pose.pose.orientation.w = 1.0
            poses.append(pose)
        path.poses = poses
        self.plan_pub.publish(path)
        markers = MarkerArray()
        for i, (fx, fy) in enumerate(((2.5, -2.0), (-2.5, 2.0), (2.4, 0.6))):
            marker = Marker()
            self._header(marker, 'map')
            marker.ns, marker.id, marker.type = 'frontiers', i, Marker.SPHERE
            marker.pose.position.x, marker.pose.position.y, marker.pose.orientation.w = fx, fy, 1.0
            marker.scale.x = marker.scale.y = marker.scale.z = 0.15
            marker.color.r, marker.color.g, marker.color.b, marker.color.a = 1.0, 0.3, 0.0, 1.0
            markers.markers.append(marker)
        self.marker_pub.publish(markers)


def main(args: list[str] | None = None) -> int:
    try:
        with zros.init(args=args):
            spin_nodes(FakeRobot())
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    return 0


if __name__ == '__main__':
    sys.exit(main(sys.argv))
