"""`zros python FILE [args...]` / `zros python -m MODULE [args...]`: run an unmodified ROS 2
Python program on zros.

The import hook of zros.import_hook maps `rclpy`, `<pkg>.msg|srv|action`, tf2_ros, launch,
cv_bridge, ... to their zros modules, then FILE runs as `python FILE args...` would run it:
as `__main__`, with its directory first on sys.path and `sys.argv == [FILE, args...]`
(`--ros-args ...` included). Everything after FILE goes to the program untouched. `-m` runs a
module the same way (`zros python -m pytest test/` runs a package's rclpy tests).
"""
from __future__ import annotations

import argparse
import importlib.util
import runpy
import sys
from pathlib import Path

__all__ = ['add_arguments', 'main_passthrough']


def add_arguments(parser: argparse.ArgumentParser) -> None:
    # (main_passthrough reads the command line itself; this parser is for --help and checks)
    parser.add_argument('-m', dest='module', nargs=argparse.REMAINDER, metavar='MODULE',
                        help='run a module as `python -m` does, then its arguments (e.g. -m pytest test/)')
    parser.add_argument('file', nargs='?', help='a ROS 2 Python program, e.g. my_pkg/my_node.py')
    parser.add_argument('argv', nargs=argparse.REMAINDER, help='arguments for the program (and --ros-args ...)')


def main_passthrough(argv: list[str]) -> int:
    from zros.errors import CliError
    from zros.import_hook import install
    if not argv or argv[0] in ('-h', '--help'):
        print(__doc__.strip())
        print('\nusage: zros python FILE [args...] [--ros-args ...]\n       zros python -m MODULE [args...]')
        return 0
    install()
    if argv[0] == '-m':
        if len(argv) < 2 or importlib.util.find_spec(argv[1]) is None:
            raise CliError(f"no module named '{argv[1]}'" if len(argv) > 1 else '-m needs a module name')
        sys.argv = [argv[1], *argv[2:]]
        sys.path.insert(0, '')
    else:
        path = Path(argv[0])
        if not path.is_file():
            raise CliError(f'no such file: {path}')
        sys.argv = [str(path), *argv[1:]]
        sys.path.insert(0, str(path.resolve().parent))
    try:
        if argv[0] == '-m':
            runpy.run_module(argv[1], run_name='__main__', alter_sys=True)
        else:
            runpy.run_path(argv[0], run_name='__main__')
    except KeyboardInterrupt:
        return 130
    except SystemExit as exc:
        code = exc.code
        if code is None or isinstance(code, int):
            return code or 0
        print(code, file=sys.stderr)
        return 1
    return 0
