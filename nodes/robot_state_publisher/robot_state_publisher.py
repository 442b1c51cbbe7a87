"""robot_state_publisher: a URDF's joints as TF frames, as ROS 2's node.

Fixed joints go once to /tf_static; moving joints (continuous, revolute, prismatic, and joints
that mimic them) go to /tf each time /joint_states brings their positions, stamped with the
joint state's time and at most `publish_frequency` times a second. The description itself is
published on /robot_description (std_msgs/String, transient local) for viewers.

    zros run robot_state_publisher robot_state_publisher --ros-args -p robot_description:="$(xacro robot.urdf.xacro)"

Parameters: robot_description (URDF text), publish_frequency (20.0 Hz), frame_prefix (''),
ignore_timestamp (False: stamp with the node clock instead of the joint state's stamp).
"""
from __future__ import annotations

import sys
from typing import Any

import zros
from zros.executors import ExternalShutdownException
from zros.node import Node
from zros.qos import DurabilityPolicy, QoSProfile, qos_profile_sensor_data
from zros.tf2_ros import StaticTransformBroadcaster, TransformBroadcaster
from zros.urdf import Robot, URDFError, parse_urdf

from interfaces.geometry_msgs.msg import TransformStamped
from interfaces.rcl_interfaces.msg import SetParametersResult
from interfaces.sensor_msgs.msg import JointState
from interfaces.std_msgs.msg import String

DESCRIPTION_QOS = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL)


def joint_transform(robot: Robot, joint: Any, positions: dict[str, float], stamp: Any, prefix: str) -> TransformStamped:
    """The TransformStamped of one joint at the given positions."""
    x, y, z, qx, qy, qz, qw = joint.transform(robot.joint_position(joint, positions))
    t = TransformStamped()
    t.header.stamp = stamp
    t.header.frame_id, t.child_frame_id = prefix + joint.parent, prefix + joint.child
    tr, rot = t.transform.translation, t.transform.rotation
    tr.x, tr.y, tr.z = x, y, z
    rot.x, rot.y, rot.z, rot.w = qx, qy, qz, qw
    return t


class RobotStatePublisher(Node):
    def __init__(self) -> None:
        super().__init__('robot_state_publisher')
        self.declare_parameter('robot_description', '')
        self.declare_parameter('publish_frequency', 20.0)
        self.declare_parameter('frame_prefix', '')
        self.declare_parameter('ignore_timestamp', False)
        self.robot = parse_urdf(self.get_parameter('robot_description').value)
        self._description_pub = self.create_publisher(String, 'robot_description', DESCRIPTION_QOS)
        self._static = StaticTransformBroadcaster(self)
        self._dynamic = TransformBroadcaster(self)
        self._last_published_ns: int | None = None
        self._missing_reported = False
        self._publish_model()
        self.add_on_set_parameters_callback(self._check_parameters)
        self.add_post_set_parameters_callback(self._apply_parameters)
        self.create_subscription(JointState, 'joint_states', self._on_joint_states, qos_profile_sensor_data)

    # -- the model -------------------------------------------------------------------------------
    def _publish_model(self) -> None:
        robot, prefix = self.robot, self._prefix()
        self._description_pub.publish(String(data=self.get_parameter('robot_description').value))
        stamp = self.get_clock().now().to_msg()
        fixed = [joint_transform(robot, j, {}, stamp, prefix) for j in robot.joints.values() if j.type == 'fixed']
        if fixed:
            self._static.sendTransform(fixed)
        moving = [j.name for j in robot.joints.values() if j.moving]
        self.get_logger().info(f"Robot '{robot.name}': {len(robot.links)} links, {len(fixed)} fixed joints on "
                               f"/tf_static, {len(moving)} moving joints from /joint_states")

    def _prefix(self) -> str:
        prefix = self.get_parameter('frame_prefix').value
        return prefix if not prefix or prefix.endswith('/') or prefix.endswith('_') else prefix + '/'

    def _check_parameters(self, parameters: list) -> SetParametersResult:
        for p in parameters:
            if p.name == 'robot_description':
                try:
                    parse_urdf(p.value)
                except URDFError as exc:
                    return SetParametersResult(successful=False, reason=str(exc))
            if p.name == 'publish_frequency' and not 0.0 <= float(p.value) <= 1000.0:
                return SetParametersResult(successful=False, reason='publish_frequency must be in [0, 1000] Hz')
        return SetParametersResult(successful=True)

    def _apply_parameters(self, parameters: list) -> None:
        if any(p.name in ('robot_description', 'frame_prefix') for p in parameters):
            self.robot = parse_urdf(self.get_parameter('robot_description').value)
            self._missing_reported = False
            self._publish_model()

    # -- joint states -------------------------------------------------------------------------------
    def _on_joint_states(self, msg: JointState) -> None:
        if len(msg.name) != len(msg.position):
            self.get_logger().warn('joint_states: name and position have different lengths; message ignored',
                                   throttle_duration_sec=5.0)
            return
        positions = dict(zip(msg.name, map(float, msg.position)))
        if self.get_parameter('ignore_timestamp').value or (msg.header.stamp.sec == 0 and msg.header.stamp.nanosec == 0):
            stamp = self.get_clock().now().to_msg()
        else:
            stamp = msg.header.stamp
        stamp_ns = stamp.sec * 1_000_000_000 + stamp.nanosec
        frequency = float(self.get_parameter('publish_frequency').value)
        last = self._last_published_ns
        if last is not None and frequency > 0 and last <= stamp_ns < last + 1e9 / frequency:
            return
        self._last_published_ns = stamp_ns
        robot, prefix = self.robot, self._prefix()
        moving = [j for j in robot.joints.values()
                  if j.moving and (j.name in positions or (j.mimic is not None and j.mimic.joint in positions))]
        if moving:
            self._dynamic.sendTransform([joint_transform(robot, j, positions, stamp, prefix) for j in moving])
        if not self._missing_reported:
            self._missing_reported = True
            missing = [j.name for j in robot.joints.values() if j.moving and j not in moving]
            if missing:
                self.get_logger().warn(f"joint_states has no position for {', '.join(missing)}: their child links "
                                       'get no transform until it does')


def main(args: list[str] | None = None) -> int:
    try:
        with zros.init(args=args):
            try:
                node = RobotStatePublisher()
            except URDFError as exc:
                hint = (' (pass it with --ros-args -p robot_description:="$(xacro robot.urdf.xacro)")'
                        if 'empty' in str(exc) else '')
                print(f'robot_state_publisher: robot_description: {exc}{hint}', file=sys.stderr)
                return 1
            zros.spin(node)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    return 0


if __name__ == '__main__':
    sys.exit(main())
