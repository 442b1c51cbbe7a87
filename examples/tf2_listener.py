"""Look up a transform between two frames once a second and print it, as `tf2_echo` does.

    python examples/tf2_listener.py odom base_footprint           # until Ctrl-C
    python examples/tf2_listener.py base_link laser --count 1

Something must publish the frames, for instance
`zros run tf2_ros static_transform_publisher --x 1 --frame-id base_link --child-frame-id laser`.
"""
from __future__ import annotations

import argparse

import zros
from zros.node import Node
from zros.tf2_ros import Buffer, TransformException, TransformListener
from zros.time import Time

from common import parse_args, run


def main(target_frame: str, source_frame: str, count: int, ros_args: list[str]) -> None:
    with zros.init(args=ros_args), Node('tf2_listener') as node:
        buffer = Buffer()
        TransformListener(buffer, node)   # fills the buffer from /tf and /tf_static
        printed = 0

        def look_up() -> None:
            nonlocal printed
            try:
                transform = buffer.lookup_transform(target_frame, source_frame, Time())   # Time(): the latest
            except TransformException as error:
                node.get_logger().info(f'Could not transform {source_frame} to {target_frame}: {error}')
                return
            t, q = transform.transform.translation, transform.transform.rotation
            node.get_logger().info(f'{target_frame} -> {source_frame}: translation [{t.x:.3f}, {t.y:.3f}, {t.z:.3f}] '
                                   f'rotation [{q.x:.3f}, {q.y:.3f}, {q.z:.3f}, {q.w:.3f}]')
            printed += 1

        node.create_timer(1.0, look_up)
        while zros.ok() and not (count and printed >= count):
            zros.spin_once(node, timeout_sec=0.5)


if __name__ == '__main__':
    parser = argparse.ArgumentParser(prog='tf2_listener', description='Print the transform between two frames.')
    parser.add_argument('target_frame', help='the frame to express the pose in (e.g. odom)')
    parser.add_argument('source_frame', help='the frame whose pose is printed (e.g. base_footprint)')
    parser.add_argument('--count', type=int, default=0, help='transforms to print, then exit (default: 0, forever)')
    args = parse_args(parser)
    run(main, args.target_frame, args.source_frame, args.count)
