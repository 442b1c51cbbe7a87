"""One simulated robot's topics: its command input and its sensor, odometry and TF outputs.

Names are relative to the robot's namespace, so the first robot (no namespace) publishes
`/scan`, `/odom`, `/tf`, ... and a robot spawned in `tb3_1` publishes `/tb3_1/scan`,
`/tb3_1/tf`, ... with the same, unprefixed frame names (`odom`, `base_footprint`), as
multi-robot ROS setups do. A robot of Gazebo Sim (ros_gz_sim's `create`) publishes where its
model's plugins say instead, on the hidden Gazebo side (zros.sim.gz_topics.RobotTopics), with the
frames they name; only zros's own ground truth stays under `sim/`. QoS are the real robot's (docs/robot.md): `/scan` is reliable with
depth 5 (Gazebo's sensor QoS made reliable), so a plain depth-10 subscription gets it, and so do
best-effort ones (AMCL, SLAM).

Messages are built once and refilled for every publication: the publisher serialises on
`publish()`, so reuse is safe, and at 20x real time the robot publishes thousands per second.
"""
from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

from zros.qos import DurabilityPolicy, QoSProfile
from zros.rotations import quaternion_from_yaw
from zros.sim import SimRobot
from zros.sim.gz_topics import RobotTopics

from interfaces.geometry_msgs.msg import Twist, TwistStamped, TransformStamped
from interfaces.nav_msgs.msg import Odometry
from interfaces.sensor_msgs.msg import Imu, JointState, LaserScan
from interfaces.std_msgs.msg import UInt32
from interfaces.tf2_msgs.msg import TFMessage

from nodes.turtlebot3_gazebo._frames import WHEEL_JOINTS, static_frames, wheel_frames

if TYPE_CHECKING:
    from zros.node import Node

__all__ = ['RobotEndpoints', 'topic_name', 'stamp', 'ABSURD_SPEED']

SCAN_QOS = QoSProfile(depth=5)
SENSOR_QOS = QoSProfile(depth=10)
TF_QOS = QoSProfile(depth=100)
LATCHED_QOS = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL)
#: [m/s] or [rad/s]: a command beyond this is a bug upstream, not a wish to go fast; ignored.
ABSURD_SPEED = 100.0
# Odometry covariance: Gazebo's diff-drive plugin fills a fixed diagonal, so do we.
_POSE_COVARIANCE = np.diag([1e-5, 1e-5, 1e12, 1e12, 1e12, 1e-3]).ravel()
_TWIST_COVARIANCE = np.diag([1e-5, 1e-5, 1e12, 1e12, 1e12, 1e-3]).ravel()


def topic_name(namespace: str, name: str) -> str:
    """`name` under a robot's namespace: relative (`scan`) without one, `ns/scan` with one."""
    namespace = namespace.strip('/')
    return f'/{namespace}/{name}' if namespace else name


def stamp(msg: Any, time_ns: int, *, field: str = 'stamp') -> None:
    """Set a header's stamp (or a Clock's `clock`) to `time_ns` of simulated time."""
    time_msg = getattr(msg, field)
    time_msg.sec, time_msg.nanosec = divmod(time_ns, 1_000_000_000)


class RobotEndpoints:
    """The publishers and the cmd_vel subscription of one robot; `destroy()` removes them all.

    Made and used by the gzserver node under its simulation lock (`on_command` is called from
    the executor; the `publish_*` methods from the simulation thread).
    """

    def __init__(self, node: 'Node', robot: SimRobot, topics: RobotTopics, *, stamped_cmd_vel: bool,
                 publish_frames: bool) -> None:
        self.robot = robot
        self.topics = topics
        self.namespace = topics.namespace.strip('/')
        self.publish_frames = publish_frames
        self._node = node
        self._warned_bad_command = False
        self.entities: list[Any] = []
        name = lambda n: topic_name(self.namespace, n)  # noqa: E731
        try:
            self.cmd_type = TwistStamped if stamped_cmd_vel else Twist
            self._keep(node.create_subscription(self.cmd_type, topics.cmd_vel, self.on_command, 10))
            self.scan_pub = self._keep(node.create_publisher(LaserScan, topics.scan, SCAN_QOS))
            self.odom_pub = self._keep(node.create_publisher(Odometry, topics.odom, SENSOR_QOS))
            self.tf_pub = self._keep(node.create_publisher(TFMessage, topics.tf, TF_QOS))
            self.joint_pub = self._keep(node.create_publisher(JointState, topics.joint_states, SENSOR_QOS))
            self.imu_pub = self._keep(node.create_publisher(Imu, topics.imu, SENSOR_QOS))
            self.truth_pub = self._keep(node.create_publisher(Odometry, name('sim/ground_truth'), SENSOR_QOS))
            self.collisions_pub = self._keep(node.create_publisher(UInt32, name('sim/collisions'), LATCHED_QOS))
            if publish_frames:
                self.tf_static_pub = self._keep(node.create_publisher(TFMessage, name('tf_static'), LATCHED_QOS))
        except Exception:
            self.destroy()
            raise
        self._build_messages()

    def _keep(self, entity: Any) -> Any:
        self.entities.append(entity)
        return entity

    def destroy(self) -> None:
        for entity in reversed(self.entities):
            if not self._node._destroy_entity(entity):
                entity.destroy()
        self.entities.clear()

    def _build_messages(self) -> None:
        spec, lidar, frames = self.robot.spec, self.robot.lidar, self.topics
        self.scan = LaserScan(angle_min=lidar.angle_min, angle_max=lidar.angle_max,
                              angle_increment=lidar.angle_increment, time_increment=0.0, scan_time=0.0,
                              range_min=lidar.range_min, range_max=lidar.range_max)
        self.scan.header.frame_id = frames.scan_frame
        self.scan.intensities = np.zeros(lidar.samples, dtype=np.float32)
        self.odom = Odometry(child_frame_id=frames.base_frame)
        self.odom.header.frame_id = frames.odom_frame
        self.odom.pose.covariance = _POSE_COVARIANCE
        self.odom.twist.covariance = _TWIST_COVARIANCE
        self.truth = Odometry(child_frame_id=frames.base_frame)
        self.truth.header.frame_id = 'world'
        self.odom_tf = TransformStamped(child_frame_id=frames.base_frame)
        self.odom_tf.header.frame_id = frames.odom_frame
        self.wheel_tfs = [TransformStamped(child_frame_id=child) for _, child, _, _ in wheel_frames(spec, (0.0, 0.0))]
        for tf, (parent, _, (x, y, z), _) in zip(self.wheel_tfs, wheel_frames(spec, (0.0, 0.0))):
            tf.header.frame_id = parent
            tf.transform.translation.x, tf.transform.translation.y, tf.transform.translation.z = x, y, z
        self.tf = TFMessage(transforms=[self.odom_tf, *self.wheel_tfs] if self.publish_frames else [self.odom_tf])
        self.joints = JointState(name=list(WHEEL_JOINTS))
        self.imu = Imu()
        self.imu.header.frame_id = frames.imu_frame
        gyro, accel = self.robot.imu_spec.gyro_noise_stddev ** 2, self.robot.imu_spec.accel_noise_stddev ** 2
        self.imu.orientation_covariance = np.diag([1e-6, 1e-6, 1e-6]).ravel()
        self.imu.angular_velocity_covariance = np.diag([gyro, gyro, gyro]).ravel()
        self.imu.linear_acceleration_covariance = np.diag([accel, accel, accel]).ravel()

    # -- input -----------------------------------------------------------------------------
    def on_command(self, msg: Any) -> None:
        """cmd_vel: the last command holds. Non-finite or absurd values are ignored, with one
        warning per robot, so a bad controller cannot crash or fling the simulator."""
        twist = msg.twist if self.cmd_type is TwistStamped else msg
        linear, angular = float(twist.linear.x), float(twist.angular.z)
        if not (math.isfinite(linear) and math.isfinite(angular)
                and abs(linear) <= ABSURD_SPEED and abs(angular) <= ABSURD_SPEED):
            if not self._warned_bad_command:
                self._warned_bad_command = True
                self._node.get_logger().warn(
                    f"Ignoring a cmd_vel for '{self.robot.name}' with linear.x={linear}, angular.z={angular} "
                    f'(non-finite, or beyond {ABSURD_SPEED:g}): it keeps its last command. '
                    'Further bad commands are ignored silently.')
            return
        self.robot.command(linear, angular)

    # -- outputs ---------------------------------------------------------------------------
    def publish_static_frames(self) -> None:
        if not self.publish_frames:
            return
        transforms = []
        for parent, child, (x, y, z) in static_frames(self.robot.spec):
            tf = TransformStamped(child_frame_id=child)
            tf.header.frame_id = parent
            tf.transform.translation.x, tf.transform.translation.y, tf.transform.translation.z = x, y, z
            transforms.append(tf)
        self.tf_static_pub.publish(TFMessage(transforms=transforms))

    def publish_odometry(self, time_ns: int) -> None:
        """odom, the odom -> base_footprint transform (+ wheels), joint_states, ground truth."""
        robot, odom = self.robot, self.robot.odometry()
        q = quaternion_from_yaw(odom.yaw)
        stamp(self.odom.header, time_ns)
        pose = self.odom.pose.pose
        pose.position.x, pose.position.y = odom.x, odom.y
        pose.orientation.x, pose.orientation.y, pose.orientation.z, pose.orientation.w = q
        self.odom.twist.twist.linear.x, self.odom.twist.twist.angular.z = odom.linear, odom.angular
        self.odom_pub.publish(self.odom)

        stamp(self.odom_tf.header, time_ns)
        t = self.odom_tf.transform
        t.translation.x, t.translation.y = odom.x, odom.y
        t.rotation.x, t.rotation.y, t.rotation.z, t.rotation.w = q
        if self.publish_frames:
            for tf, (_, _, _, rotation) in zip(self.wheel_tfs, wheel_frames(robot.spec, robot.wheel_positions)):
                stamp(tf.header, time_ns)
                r = tf.transform.rotation
                r.x, r.y, r.z, r.w = rotation
        self.tf_pub.publish(self.tf)

        stamp(self.joints.header, time_ns)
        self.joints.position = np.array(robot.wheel_positions)
        self.joints.velocity = np.array(robot.wheel_velocities)
        self.joint_pub.publish(self.joints)

        truth, (linear, angular) = robot.pose, robot.velocity
        stamp(self.truth.header, time_ns)
        pose = self.truth.pose.pose
        pose.position.x, pose.position.y = truth.x, truth.y
        pose.orientation.x, pose.orientation.y, pose.orientation.z, pose.orientation.w = quaternion_from_yaw(truth.yaw)
        self.truth.twist.twist.linear.x, self.truth.twist.twist.angular.z = linear, angular
        self.truth_pub.publish(self.truth)

    def publish_scan(self, time_ns: int) -> None:
        stamp(self.scan.header, time_ns)
        self.scan.ranges = self.robot.scan()
        self.scan_pub.publish(self.scan)

    def publish_imu(self, time_ns: int) -> None:
        reading = self.robot.imu()
        stamp(self.imu.header, time_ns)
        o = self.imu.orientation
        o.x, o.y, o.z, o.w = quaternion_from_yaw(reading.yaw)
        av, la = self.imu.angular_velocity, self.imu.linear_acceleration
        av.x, av.y, av.z = reading.angular_velocity
        la.x, la.y, la.z = reading.linear_acceleration
        self.imu_pub.publish(self.imu)

    def publish_collisions(self) -> None:
        self.collisions_pub.publish(UInt32(data=self.robot.collisions))
