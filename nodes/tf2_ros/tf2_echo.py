"""`tf2_echo SOURCE TARGET [RATE]`: print the transform between two frames, as tf2_ros's tool.

As upstream, it looks up `lookup_transform(SOURCE, TARGET, latest)`: the pose of TARGET in
SOURCE, i.e. the transform that takes data from TARGET into SOURCE. The output format is
upstream's (3 decimals, RPY in radians and degrees, the 4x4 matrix); the nanoseconds of the
stamp are zero-padded, where upstream prints `5` for 000000005.
"""
from __future__ import annotations

import sys
import time

import zros
from zros.executors import ExternalShutdownException, SingleThreadedExecutor
from zros.node import Node
from zros.tf2_ros import Buffer, Time, TransformException, TransformListener
from zros.tf2_ros.transform_math import to_matrix
from zros.tf_transformations import euler_from_quaternion
from zros.utilities import remove_ros_args

USAGE = """Usage: tf2_echo source_frame target_frame [echo_rate]

This will echo the transform from the coordinate frame of the source_frame
to the coordinate frame of the target_frame. 
Note: This is the transform to get data from target_frame into the source_frame.
Default echo rate is 1 if echo_rate is not given."""  # noqa: W291 - tf2_echo's own text, its trailing space included


def format_transform(transform) -> str:
    """The text tf2_echo prints for one TransformStamped."""
    stamp, p, q = transform.header.stamp, transform.transform.translation, transform.transform.rotation
    roll, pitch, yaw = euler_from_quaternion([q.x, q.y, q.z, q.w])
    deg = 180.0 / 3.141592653589793
    m = to_matrix((p.x, p.y, p.z, q.x, q.y, q.z, q.w))
    lines = [f'At time {stamp.sec}.{stamp.nanosec:09d}',
             f'- Translation: [{p.x:.3f}, {p.y:.3f}, {p.z:.3f}]',
             f'- Rotation: in Quaternion [{q.x:.3f}, {q.y:.3f}, {q.z:.3f}, {q.w:.3f}]',
             f'- Rotation: in RPY (radian) [{roll:.3f}, {pitch:.3f}, {yaw:.3f}]',
             f'- Rotation: in RPY (degree) [{roll * deg:.3f}, {pitch * deg:.3f}, {yaw * deg:.3f}]',
             '- Matrix:']
    lines += [''.join(f' {v:6.3f}' for v in row) for row in m]
    return '\n'.join(lines)


def main(args: list[str] | None = None) -> int:
    argv = list(sys.argv if args is None else args)
    plain = remove_ros_args(argv)
    if len(plain) not in (3, 4):
        print(USAGE)
        return 1
    rate = 1.0
    if len(plain) == 4:
        try:
            rate = float(plain[3])
        except ValueError:
            print(f"Failed to convert rate argument '{plain[3]}' to a floating-point number", file=sys.stderr)
            return 2
        if not rate > 0:
            print(f"Rate argument '{plain[3]}' must be a positive number", file=sys.stderr)
            return 2
    source, target = plain[1], plain[2]
    period = 1.0 / rate
    try:
        with zros.init(args=argv):
            node = Node('tf2_echo')
            buffer = Buffer()
            TransformListener(buffer, node)
            executor = SingleThreadedExecutor()
            executor.add_node(node)

            def sleep_spinning(seconds: float) -> None:
                deadline = time.monotonic() + seconds
                while zros.ok() and (remaining := deadline - time.monotonic()) > 0:
                    executor.spin_once(timeout_sec=remaining)

            last_wait_log = 0.0
            while zros.ok():
                ok, reason = buffer.can_transform(source, target, Time(), return_debug_tuple=True)
                if ok:
                    break
                if time.monotonic() - last_wait_log >= 1.0:
                    last_wait_log = time.monotonic()
                    node.get_logger().info(f'Waiting for transform {source} ->  {target}: {reason}')
                sleep_spinning(min(period, 0.1))
            while zros.ok():
                try:
                    print(format_transform(buffer.lookup_transform(source, target, Time())), flush=True)
                except TransformException as exc:
                    print(f'Failure at {node.get_clock().now().nanoseconds / 1e9}\nException thrown:{exc}\n'
                          f'The current list of frames is:\n{buffer.all_frames_as_string()}', flush=True)
                sleep_spinning(period)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    return 0


if __name__ == '__main__':
    sys.exit(main())
