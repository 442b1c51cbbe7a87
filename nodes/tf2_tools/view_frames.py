"""`view_frames`: listen to /tf and /tf_static for a while, then draw the frame tree.

Writes what tf2_tools' tool writes: `frames_YYYY-MM-DD_HH.MM.SS.gv` (Graphviz DOT) and
`frames_YYYY-MM-DD_HH.MM.SS.pdf`. ROS renders the PDF with Graphviz's `dot`; zros lays the tree
out and writes the PDF itself (zros.tf2_ros.frame_graph), so it appears on any machine without a
system package (`dot -Tpdf frames_<date>.gv -o ...` still renders Graphviz's version).
`-o NAME` fixes the file names (NAME.gv, NAME.pdf).
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import zros
from zros.executors import ExternalShutdownException, SingleThreadedExecutor
from zros.node import Node
from zros.tf2_ros import Buffer, TransformListener
from zros.tf2_ros.frame_graph import to_dot, to_pdf
from zros.utilities import remove_ros_args


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog='view_frames',
                                     description='Create a diagram of the TF frames being broadcast over ROS')
    parser.add_argument('--wait-time', '-t', type=float, default=5.0,
                        help='Listen to the /tf topic for this many seconds before rendering the frame tree')
    parser.add_argument('-o', '--output', help='Output filename (without extension)')
    return parser


def main(args: list[str] | None = None) -> int:
    argv = list(sys.argv if args is None else args)
    options = _parser().parse_args(remove_ros_args(argv)[1:])
    try:
        with zros.init(args=argv):
            node = Node('view_frames')
            buffer = Buffer(node=node)
            TransformListener(buffer, node)
            executor = SingleThreadedExecutor()
            executor.add_node(node)
            node.get_logger().info(f'Listening to tf data for {options.wait_time} seconds...')
            deadline = time.monotonic() + options.wait_time
            while zros.ok() and (remaining := deadline - time.monotonic()) > 0:
                executor.spin_once(timeout_sec=remaining)
            base = options.output or f"frames_{time.strftime('%Y-%m-%d_%H.%M.%S')}"
            frames = buffer.frames()
            recorded = node.get_clock().now().nanoseconds / 1e9
            dot_path = Path(f'{base}.gv')
            dot_path.write_text(to_dot(frames, recorded))
            picture = Path(f'{base}.pdf')
            node.get_logger().info(f'Generating graph in {picture} file...')
            picture.write_bytes(to_pdf(frames, recorded))
            if not frames:
                node.get_logger().warn('No tf data received: is anything publishing /tf or /tf_static?')
            print(f'{len(frames)} frames: {dot_path} and {picture}')
    except (KeyboardInterrupt, ExternalShutdownException):
        return 130
    return 0


if __name__ == '__main__':
    sys.exit(main())
