"""One simulated robot's topics: its command input and its sensor, odometry and TF outputs.

What a robot publishes, on which topic, in which frame and how often is what its model file's
Gazebo plugins say (zros.sim.model_file.RobotModel: the diff drive's odom and TF, the ray
sensor, the IMU, the joint state publisher); a TurtleBot3 without a file is ROBOTIS's model.
Names are relative to the robot's namespace, so the first robot (no namespace) publishes
`/scan`, `/odom`, `/tf`, ... and a robot spawned in `tb3_1` publishes `/tb3_1/scan`,
`/tb3_1/tf`, ... with the same, unprefixed frame names (`odom`, `base_footprint`), as
multi-robot ROS setups do. A robot of Gazebo Sim (ros_gz_sim's `create`) publishes where its
model's plugins say instead, on the hidden Gazebo side (zros.sim.gz_topics.RobotTopics), with the
frames they name; only zros's own ground truth stays under `sim/`. Where a robot's outputs go
and in which frames is one RobotTopics (`model_topics` for Gazebo classic's plugins); whether and
how often each is published is its model's. Each output keeps its own schedule in simulated time
(`publish_due`): a scan at 0.2 s, 0.4 s, ... for a 5 Hz sensor. QoS are the real robot's (docs/robot.md): `/scan` is reliable with
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
from zros.sim.gz_topics import RobotTopics, ros_topics
from zros.sim.model_file import RobotModel

from interfaces.geometry_msgs.msg import Twist, TwistStamped, TransformStamped
from interfaces.nav_msgs.msg import Odometry
from interfaces.sensor_msgs.msg import Imu, JointState, LaserScan
from interfaces.std_msgs.msg import UInt32
from interfaces.tf2_msgs.msg import TFMessage

from nodes.turtlebot3_gazebo._frames import WHEEL_JOINTS, static_frames, wheel_frames

if TYPE_CHECKING:
    from zros.node import Node

__all__ = ['RobotEndpoints', 'model_topics', 'topic_name', 'stamp', 'ABSURD_SPEED', 'TRUTH_RATE']

SCAN_QOS = QoSProfile(depth=5)
SENSOR_QOS = QoSProfile(depth=10)
TF_QOS = QoSProfile(depth=100)
LATCHED_QOS = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL)
#: [m/s] or [rad/s]: a command beyond this is a bug upstream, not a wish to go fast; ignored.
ABSURD_SPEED = 100.0
TRUTH_RATE = 30.0          # [Hz] sim/ground_truth
# Odometry covariance: Gazebo's diff-drive plugin fills a fixed diagonal, so do we.
_POSE_COVARIANCE = np.diag([1e-5, 1e-5, 1e12, 1e12, 1e12, 1e-3]).ravel()
_TWIST_COVARIANCE = np.diag([1e-5, 1e-5, 1e12, 1e12, 1e12, 1e-3]).ravel()


def topic_name(namespace: str, name: str) -> str:
    """`name` under a robot's namespace: relative (`scan`) without one, `ns/scan` with one."""
    namespace = namespace.strip('/')
    return f'/{namespace}/{name}' if namespace else name


def model_topics(model: RobotModel, namespace: str) -> RobotTopics:
    """Where a robot's outputs go in ROS under its `namespace`, and their frames, as its model's
    Gazebo classic plugins name them (a Gazebo Sim model's names are Gazebo's: the TurtleBot3's
    ROS names instead, as if bridged)."""
    if model.topics is not None:
        return ros_topics(namespace)
    drive, name = model.drive, lambda n: topic_name(namespace, n)  # noqa: E731
    scan, imu = model.scan, model.imu_output
    return RobotTopics(cmd_vel=name(drive.cmd_vel_topic), odom=name(drive.odom_topic), tf=name('tf'),
                       joint_states=name(model.joint_states.topic if model.joint_states else 'joint_states'),
                       scan=name(scan.topic if scan else 'scan'), imu=name(imu.topic if imu else 'imu'),
                       namespace=namespace.strip('/'), odom_frame=drive.odometry_frame,
                       base_frame=drive.robot_base_frame, scan_frame=scan.frame if scan else 'base_scan',
                       imu_frame=imu.frame if imu else 'imu_link')


def stamp(msg: Any, time_ns: int, *, field: str = 'stamp') -> None:
    """Set a header's stamp (or a Clock's `clock`) to `time_ns` of simulated time."""
    time_msg = getattr(msg, field)
    time_msg.sec, time_msg.nanosec = divmod(time_ns, 1_000_000_000)


class RobotEndpoints:
    """The publishers and the cmd_vel subscription of one robot; `destroy()` removes them all.

    Made and used by the gzserver node under its simulation lock (`on_command` is called from
    the executor; the `publish_*` methods from the simulation thread).
    """

    def __init__(self, node: 'Node', robot: SimRobot, model: RobotModel, topics: RobotTopics, *,
                 stamped_cmd_vel: bool, publish_frames: bool) -> None:
        """`model`: what the robot publishes and how often; `topics`: where, and in which frames.
        `publish_frames`: also publish the fixed frames (tf_static) and the wheels (tf), which
        Gazebo leaves to robot_state_publisher: for a robot no launch file describes."""
        self.robot = robot
        self.model = model
        self.topics = topics
        self.namespace = topics.namespace.strip('/')
        self.publish_frames = publish_frames
        drive = model.drive
        self._wheel_tf = publish_frames or drive.publish_wheel_tf
        self._any_tf = drive.publish_odom_tf or self._wheel_tf
        self.odom_pub = self.tf_pub = self.joint_pub = self.imu_pub = self.scan_pub = None
        self._node = node
        self._warned_bad_command = False
        self.entities: list[Any] = []
        name = lambda n: topic_name(self.namespace, n)  # noqa: E731
        try:
            self.cmd_type = TwistStamped if stamped_cmd_vel else Twist
            self._keep(node.create_subscription(self.cmd_type, topics.cmd_vel, self.on_command, 10))
            if model.scan is not None:
                self.scan_pub = self._keep(node.create_publisher(LaserScan, topics.scan, SCAN_QOS))
            if drive.publish_odom:
                self.odom_pub = self._keep(node.create_publisher(Odometry, topics.odom, SENSOR_QOS))
            if self._any_tf:
                self.tf_pub = self._keep(node.create_publisher(TFMessage, topics.tf, TF_QOS))
            if model.joint_states is not None:
                self.joint_pub = self._keep(node.create_publisher(JointState, topics.joint_states, SENSOR_QOS))
            if model.imu_output is not None:
                self.imu_pub = self._keep(node.create_publisher(Imu, topics.imu, SENSOR_QOS))
            self.truth_pub = self._keep(node.create_publisher(Odometry, name('sim/ground_truth'), SENSOR_QOS))
            self.collisions_pub = self._keep(node.create_publisher(UInt32, name('sim/collisions'), LATCHED_QOS))
            if publish_frames:
                self.tf_static_pub = self._keep(node.create_publisher(TFMessage, name('tf_static'), LATCHED_QOS))
        except Exception:
            self.destroy()
            raise
        self._build_messages()
        self.schedule(0)

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
        drive = self.model.drive
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
        self.tf = TFMessage(transforms=([self.odom_tf] if drive.publish_odom_tf else [])
                            + (self.wheel_tfs if self._wheel_tf else []))
        joints = self.model.joint_states.joints if self.model.joint_states else ()
        self._joint_index = [WHEEL_JOINTS.index(j) for j in joints if j in WHEEL_JOINTS]   # others: unknown here
        self.joints = JointState(name=[WHEEL_JOINTS[i] for i in self._joint_index])
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
    def schedule(self, time_ns: int) -> None:
        """Every output falls due one of its periods after `time_ns` (at spawn and reset)."""
        model = self.model
        rates = {'odometry': model.drive.update_rate, 'truth': TRUTH_RATE,
                 'joints': model.joint_states.rate if model.joint_states else 0.0,
                 'scan': model.scan.rate if model.scan else 0.0,
                 'imu': model.imu_output.rate if model.imu_output else 0.0}
        self._periods = {name: int(round(1e9 / rate)) for name, rate in rates.items() if rate > 0}
        self._due = {name: time_ns + period for name, period in self._periods.items()}

    def publish_due(self, time_ns: int) -> None:
        """Publish whatever falls due at `time_ns` (after a physics step), IMU first as it is
        the most frequent."""
        for name in ('imu', 'odometry', 'joints', 'truth', 'scan'):
            due = self._due.get(name)
            if due is not None and time_ns >= due:
                self._due[name] = due + self._periods[name]
                getattr(self, f'publish_{name}')(time_ns)

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
        """The diff drive's outputs: odom, the odom -> base_footprint transform, the wheels' TF."""
        robot, odom = self.robot, self.robot.odometry()
        q = quaternion_from_yaw(odom.yaw)
        if self.odom_pub is not None:
            stamp(self.odom.header, time_ns)
            pose = self.odom.pose.pose
            pose.position.x, pose.position.y = odom.x, odom.y
            pose.orientation.x, pose.orientation.y, pose.orientation.z, pose.orientation.w = q
            self.odom.twist.twist.linear.x, self.odom.twist.twist.angular.z = odom.linear, odom.angular
            self.odom_pub.publish(self.odom)
        if self.tf_pub is None:
            return
        stamp(self.odom_tf.header, time_ns)
        t = self.odom_tf.transform
        t.translation.x, t.translation.y = odom.x, odom.y
        t.rotation.x, t.rotation.y, t.rotation.z, t.rotation.w = q
        if self._wheel_tf:
            for tf, (_, _, _, rotation) in zip(self.wheel_tfs, wheel_frames(robot.spec, robot.wheel_positions)):
                stamp(tf.header, time_ns)
                r = tf.transform.rotation
                r.x, r.y, r.z, r.w = rotation
        self.tf_pub.publish(self.tf)

    def publish_joints(self, time_ns: int) -> None:
        stamp(self.joints.header, time_ns)
        positions, velocities = self.robot.wheel_positions, self.robot.wheel_velocities
        self.joints.position = np.array([positions[i] for i in self._joint_index])
        self.joints.velocity = np.array([velocities[i] for i in self._joint_index])
        self.joint_pub.publish(self.joints)

    def publish_truth(self, time_ns: int) -> None:
        robot = self.robot
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
