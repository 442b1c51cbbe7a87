"""map_saver_cli: save the map being published on /map to NAME.yaml + NAME.pgm, as nav2's tool.

    zros run nav2_map_server map_saver_cli -f ~/map
    zros run nav2_map_server map_saver_cli -f ~/map --mode scale --fmt png --occ 0.65 --free 0.196

It subscribes to the map topic with transient local durability (so it gets the last map at once
from SLAM or map_server), waits up to `save_map_timeout` seconds (parameter, default 5; nav2's 2 s
is shorter than many SLAM nodes' publishing period), and writes the files by zros.map_io's rules.
Exit code 0 when saved, 1 otherwise (a bad argument, no map, a file that cannot be written).
"""
from __future__ import annotations

import sys
import threading
import time

import zros
from zros.executors import ExternalShutdownException, SingleThreadedExecutor
from zros.map_io import DEFAULT_FREE_THRESH, DEFAULT_OCCUPIED_THRESH, IMAGE_FORMATS, MAP_MODES
from zros.node import Node
from zros.utilities import remove_ros_args

from nodes.nav2_map_server._saver import DEFAULT_TIMEOUT, save_map_from_topic

USAGE = """Usage:
  map_saver_cli [arguments] [--ros-args ROS remapping args]

Arguments:
  -h/--help
  -t <map_topic>
  -f <mapname>
  --occ <threshold_occupied>
  --free <threshold_free>
  --fmt <image_format>
  --mode trinary(default)/scale/raw

NOTE: --ros-args should be passed at the end of command line"""

_FLAGS = {'-t': 'topic', '-f': 'name', '--occ': 'occupied_thresh', '--free': 'free_thresh', '--fmt': 'image_format',
          '--mode': 'mode'}


class ArgumentError(ValueError):
    """The command line cannot be used; the text says why."""


def parse_arguments(argv: list[str]) -> dict | None:
    """The options of a map_saver_cli command line (ROS arguments removed), or None for --help."""
    options: dict = {'topic': 'map', 'name': '', 'occupied_thresh': DEFAULT_OCCUPIED_THRESH,
                     'free_thresh': DEFAULT_FREE_THRESH, 'image_format': None, 'mode': 'trinary'}
    i = 0
    while i < len(argv):
        arg = argv[i]
        if arg in ('-h', '--help'):
            return None
        if arg not in _FLAGS:
            raise ArgumentError(f'Wrong argument: {arg}')
        if i + 1 >= len(argv):
            raise ArgumentError(f'Wrong argument: {arg} should be followed by a value.')
        key, value = _FLAGS[arg], argv[i + 1]
        if key in ('occupied_thresh', 'free_thresh'):
            try:
                options[key] = float(value)
            except ValueError:
                raise ArgumentError(f'{arg}: not a number: {value!r}') from None
        elif key == 'mode' and value not in MAP_MODES:
            raise ArgumentError(f"{arg}: unsupported map mode '{value}' (trinary, scale or raw)")
        elif key == 'image_format' and value.lower() not in IMAGE_FORMATS:
            raise ArgumentError(f"{arg}: unsupported image format '{value}' (pgm or png)")
        else:
            options[key] = value.lower() if key == 'image_format' else value
        i += 2
    if not 0.0 <= options['free_thresh'] < options['occupied_thresh'] <= 1.0:
        raise ArgumentError(f"thresholds: need 0 <= --free ({options['free_thresh']:g}) < --occ "
                            f"({options['occupied_thresh']:g}) <= 1")
    if options['mode'] == 'scale' and options['image_format'] == 'pgm':
        raise ArgumentError("--mode scale needs transparency, which pgm has not: use --fmt png")
    return options


def main(args: list[str] | None = None) -> int:
    argv = list(sys.argv if args is None else args)
    try:
        options = parse_arguments(remove_ros_args(argv)[1:])
    except ArgumentError as exc:
        print(f'map_saver_cli: {exc} (see --help)', file=sys.stderr)
        return 1
    if options is None:
        print(USAGE)
        return 0
    topic, name = options.pop('topic'), options.pop('name')
    try:
        with zros.init(args=argv):
            node = Node('map_saver')
            timeout = float(node.declare_parameter('save_map_timeout', DEFAULT_TIMEOUT).value)
            transient = bool(node.declare_parameter('map_subscribe_transient_local', True).value)
            if not name:
                name = f'map_{int(time.time())}'
                node.get_logger().warn(f'Map file unspecified. Map will be saved to {name} file')
            executor = SingleThreadedExecutor()
            executor.add_node(node)
            threading.Thread(target=_spin, args=(executor,), name='map_saver_cli', daemon=True).start()
            saved = save_map_from_topic(node, topic, name, timeout=timeout, transient_local=transient, **options)
            executor.shutdown(timeout_sec=1.0)
            return 0 if saved else 1
    except (KeyboardInterrupt, ExternalShutdownException):
        return 130


def _spin(executor: SingleThreadedExecutor) -> None:
    try:
        executor.spin()
    except ExternalShutdownException:
        pass


if __name__ == '__main__':
    sys.exit(main(sys.argv))
