"""`view_frames`: listen to /tf and /tf_static for a while, then draw the frame tree.

Writes `frames_YYYY-MM-DD_HH.MM.SS.gv` (Graphviz DOT, as tf2_tools' tool) and a PDF made by
Graphviz's `dot` when it is installed; otherwise an SVG drawn by zros itself, so the tree can be
looked at on any machine. `-o NAME` fixes the file names (NAME.gv, NAME.pdf or NAME.svg).
"""
from __future__ import annotations

import argparse
import shutil
import subprocess
import sys
import time
from pathlib import Path

import zros
from zros.executors import ExternalShutdownException, SingleThreadedExecutor
from zros.node import Node
from zros.tf2_ros import Buffer, TransformListener
from zros.tf2_ros.frame_graph import to_dot, to_svg
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
            dot = shutil.which('dot')
            if dot is not None:
                picture = Path(f'{base}.pdf')
                node.get_logger().info(f'Generating graph in {picture} file...')
                done = subprocess.run([dot, '-Tpdf', str(dot_path), '-o', str(picture)], capture_output=True, text=True)
                if done.returncode != 0:
                    node.get_logger().error(f'dot failed: {done.stderr.strip()}')
                    return 1
            else:
                picture = Path(f'{base}.svg')
                node.get_logger().info(f'Graphviz (dot) is not installed: generating graph in {picture} file...')
                picture.write_text(to_svg(frames, recorded))
            if not frames:
                node.get_logger().warn('No tf data received: is anything publishing /tf or /tf_static?')
            print(f'{len(frames)} frames: {dot_path} and {picture}')
    except (KeyboardInterrupt, ExternalShutdownException):
        return 130
    return 0


if __name__ == '__main__':
    sys.exit(main())
