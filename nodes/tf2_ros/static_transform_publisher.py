"""`static_transform_publisher`: publish one static transform on /tf_static until stopped.

Both of ROS 2's argument forms work:

    static_transform_publisher --x 1 --y 0 --z 0.5 --yaw 1.57 --frame-id base_link --child-frame-id laser
    static_transform_publisher 1 0 0.5 1.57 0 0 base_link laser            # x y z yaw pitch roll (deprecated)
    static_transform_publisher 1 0 0.5 0 0 0.707 0.707 base_link laser     # x y z qx qy qz qw (deprecated)
"""
from __future__ import annotations

import random
import string
import sys

import zros
from zros.executors import ExternalShutdownException
from zros.node import Node
from zros.tf2_ros import StaticTransformBroadcaster
from zros.tf_transformations import quaternion_from_euler
from zros.utilities import remove_ros_args

USAGE = """usage: static_transform_publisher [--x X] [--y Y] [--z Z] [--qx QX] [--qy QY] [--qz QZ] [--qw QW] \
[--roll ROLL] [--pitch PITCH] [--yaw YAW] --frame-id FRAME_ID --child-frame-id CHILD_FRAME_ID

A command line utility for manually sending a static transform.

If no translation or orientation is provided, the identity transform will be published.

The translation offsets are in meters.

The rotation may be provided with roll, pitch, yaw euler angles in radians, or as a quaternion.

required arguments:
  --frame-id FRAME_ID parent frame
  --child-frame-id CHILD_FRAME_ID child frame id

optional arguments:
  --x X                 x component of translation
  --y Y                 y component of translation
  --z Z                 z component of translation
  --qx QX               x component of quaternion rotation
  --qy QY               y component of quaternion rotation
  --qz QZ               z component of quaternion rotation
  --qw QW               w component of quaternion rotation
  --roll ROLL           roll component Euler rotation
  --pitch PITCH         pitch component Euler rotation
  --yaw YAW             yaw component Euler rotation

old-style (deprecated) positional forms:
  x y z yaw pitch roll frame_id child_frame_id
  x y z qx qy qz qw frame_id child_frame_id"""

_NUMBER_FLAGS = {'--x': 'x', '--y': 'y', '--z': 'z', '--qx': 'qx', '--qy': 'qy', '--qz': 'qz', '--qw': 'qw',
                 '--roll': 'roll', '--pitch': 'pitch', '--yaw': 'yaw'}
_TEXT_FLAGS = {'--frame-id': 'frame_id', '--child-frame-id': 'child_frame_id'}


class ArgumentError(ValueError):
    """The command line cannot be understood; the text says why."""


def _number(name: str, text: str) -> float:
    try:
        return float(text)
    except ValueError:
        raise ArgumentError(f'Failed to parse {name} argument as float') from None


def parse_arguments(argv: list[str]) -> tuple[dict | None, bool]:
    """({x, y, z, qx, qy, qz, qw, frame_id, child_frame_id}, old_style), or (None, False) for
    --help. Raises ArgumentError with tf2_ros's wording."""
    values: dict = {'x': 0.0, 'y': 0.0, 'z': 0.0, 'qx': 0.0, 'qy': 0.0, 'qz': 0.0, 'qw': 1.0,
                    'frame_id': '', 'child_frame_id': ''}
    euler = {'roll': 0.0, 'pitch': 0.0, 'yaw': 0.0}
    seen: set[str] = set()
    positional: list[str] = []
    i = 0
    while i < len(argv):
        arg = argv[i]
        if arg in ('-h', '--help'):
            return None, False
        if arg in _NUMBER_FLAGS or arg in _TEXT_FLAGS:
            if i + 1 >= len(argv):
                raise ArgumentError(f'Not enough arguments for {arg}')
            i += 1
            if arg in _NUMBER_FLAGS:
                key = _NUMBER_FLAGS[arg]
                (euler if key in euler else values)[key] = _number(arg, argv[i])
            else:
                values[_TEXT_FLAGS[arg]] = argv[i]
            seen.add('rpy' if arg in ('--roll', '--pitch', '--yaw') else
                     'quat' if arg.startswith('--q') else 'frame' if arg in _TEXT_FLAGS else 'trans')
        else:
            positional.append(arg)
        i += 1
    if {'rpy', 'quat'} <= seen:
        raise ArgumentError('Cannot specify both quaternion and Euler rotations')
    old_style = len(positional) in (8, 9)
    if old_style:
        if seen:
            raise ArgumentError('Cannot specify both new-style (flags) and old-style (arguments)')
        for key, text in zip(('x', 'y', 'z'), positional):
            values[key] = _number(key, text)
        if len(positional) == 8:
            for key, text in zip(('yaw', 'pitch', 'roll'), positional[3:6]):
                euler[key] = _number(key, text)
            seen.add('rpy')
        else:
            for key, text in zip(('qx', 'qy', 'qz', 'qw'), positional[3:7]):
                values[key] = _number(key, text)
        values['frame_id'], values['child_frame_id'] = positional[-2], positional[-1]
    elif positional:
        raise ArgumentError(f'Extra unparsed arguments on command-line: {" ".join(positional)}')
    if 'rpy' in seen:
        values['qx'], values['qy'], values['qz'], values['qw'] = map(
            float, quaternion_from_euler(euler['roll'], euler['pitch'], euler['yaw']))
    if not values['frame_id']:
        raise ArgumentError('Frame id must not be empty')
    if not values['child_frame_id']:
        raise ArgumentError('Child frame id must not be empty')
    if values['frame_id'] == values['child_frame_id']:
        raise ArgumentError(f"cannot publish static transform from '{values['frame_id']}' to "
                            f"'{values['child_frame_id']}'")
    return values, old_style


def _unique_name() -> str:
    return 'static_transform_publisher_' + ''.join(random.choices(string.ascii_letters + string.digits, k=16))


def main(args: list[str] | None = None) -> int:
    argv = list(sys.argv if args is None else args)
    try:
        values, old_style = parse_arguments(remove_ros_args(argv)[1:])
    except ArgumentError as exc:
        print(f'static_transform_publisher: error parsing command line arguments: {exc} (see --help)',
              file=sys.stderr)
        return 1
    if values is None:
        print(USAGE)
        return 0
    from interfaces.geometry_msgs.msg import TransformStamped
    try:
        with zros.init(args=argv):
            node = Node(_unique_name())
            if old_style:
                node.get_logger().warn('Old-style arguments are deprecated; see --help for new-style arguments')
            for name, key in (('translation.x', 'x'), ('translation.y', 'y'), ('translation.z', 'z'),
                              ('rotation.x', 'qx'), ('rotation.y', 'qy'), ('rotation.z', 'qz'),
                              ('rotation.w', 'qw'), ('frame_id', 'frame_id'), ('child_frame_id', 'child_frame_id')):
                node.declare_parameter(name, values[key])
            t = TransformStamped()
            t.header.stamp = node.get_clock().now().to_msg()
            t.header.frame_id, t.child_frame_id = values['frame_id'], values['child_frame_id']
            p, q = t.transform.translation, t.transform.rotation
            p.x, p.y, p.z = values['x'], values['y'], values['z']
            q.x, q.y, q.z, q.w = values['qx'], values['qy'], values['qz'], values['qw']
            broadcaster = StaticTransformBroadcaster(node)
            broadcaster.sendTransform(t)
            node.get_logger().info(
                'Spinning until stopped - publishing transform\n'
                f"translation: ('{p.x:f}', '{p.y:f}', '{p.z:f}')\n"
                f"rotation: ('{q.x:f}', '{q.y:f}', '{q.z:f}', '{q.w:f}')\n"
                f"from '{t.header.frame_id}' to '{t.child_frame_id}'")
            zros.spin(node)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    return 0


if __name__ == '__main__':
    sys.exit(main())
