"""`zros test`: run a launch test file (ROS 2's `launch_test`).

    zros test test/test_talker_listener.py [name:=value ...] [--log-dir DIR] [-d]

The file is read under the import hook (`import launch_testing`, `from launch import ...`,
`import rclpy` are zros's), its launch runs in a private zros domain, the active tests run once
it reaches ReadyToTest and the post-shutdown tests after it ended. Launch arguments are given to
the launch and to the tests as `test_args`. Exit status 0 when every test passed, 1 otherwise;
a file that cannot run is one line on stderr.
"""
from __future__ import annotations

import argparse
import sys

__all__ = ['add_arguments', 'main']


def _add_options(parser: argparse.ArgumentParser) -> None:
    parser.add_argument('--log-dir', metavar='DIR', default=None,
                        help="write the launch's logs to DIR (default: $ZROS_LOG_DIR or ~/.zros/log, timestamped)")
    parser.add_argument('-d', '--debug', action='store_true', help="print the supervisor's debug messages")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    _add_options(parser)
    parser.add_argument('items', nargs=argparse.REMAINDER, metavar='FILE [name:=value ...]',
                        help='the launch test (defines generate_test_description), then launch arguments')
    parser.set_defaults(handler=main)


def _late_options(items: list[str]) -> argparse.Namespace:
    """Options written after the file (`zros test t.py x:=1 --log-dir d`), parsed with the items."""
    parser = argparse.ArgumentParser(prog='zros test', add_help=False)
    _add_options(parser)
    parser.add_argument('items', nargs='*')
    return parser.parse_intermixed_args(items)


def _report(outcome: object) -> None:
    failures = outcome.failures()
    if outcome.problem:
        print(f'zros test: {outcome.problem}', file=sys.stderr)
    elif failures:
        print(f"zros test: {len(failures)} test(s) failed: {', '.join(name for name, _ in failures)}", file=sys.stderr)


def main(args: argparse.Namespace) -> int:
    from zros.launch import LaunchError, parse_launch_arguments
    from zros.launch.supervisor import make_log_dir
    from zros.launch_testing.loader import LaunchTest
    from zros.launch_testing.runner import run_launch_test
    late = _late_options(list(args.items))
    if not late.items:
        from zros.errors import CliError
        raise CliError('usage: zros test FILE [name:=value ...] (see zros test -h)')
    try:
        launch_arguments = parse_launch_arguments(late.items[1:])
        test = LaunchTest.from_file(late.items[0])
        outcome = run_launch_test(test, launch_arguments=launch_arguments,
                                  log_dir=make_log_dir(late.log_dir or args.log_dir), debug=args.debug or late.debug)
    except LaunchError as exc:
        print(str(exc), file=sys.stderr)
        return 1
    _report(outcome)
    return 0 if outcome.ok else 1
