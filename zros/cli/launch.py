"""`zros launch`: run a launch file, Python (`*.launch.py`) or YAML (like ros2 launch).

    zros launch FILE [name:=value ...] [--print] [--show-args] [--log-dir DIR] [--debug]
    zros launch PKG FILE [name:=value ...]      # FILE in the package's share directory or its launch/

Session options (--connect, --listen, --discovery, --domain-id, --zenoh-config; see
docs/multi-machine.md) set the ZROS_* environment of the supervisor and every process it starts.
`--router` runs a Zenoh router in the supervisor for the launch's duration (the robot's side of a
multi-machine set-up in one command).

Options may come before or after the file. Launch-file errors print one line,
`file:line: <tag>: <key>: reason`, and nothing is started. The launch system itself
(zros.launch) is imported only when this verb runs.
"""
from __future__ import annotations

import argparse
import os
import sys

__all__ = ['add_arguments', 'main']


def _add_options(parser: argparse.ArgumentParser) -> None:
    parser.add_argument('-p', '--print', '--print-description', dest='print_plan', action='store_true',
                        help='print the resolved plan (processes, command lines, env, params); start nothing')
    parser.add_argument('-s', '--show-args', '--show-arguments', dest='show_args', action='store_true',
                        help='list the launch arguments (defaults, descriptions, choices) and exit')
    parser.add_argument('--log-dir', metavar='DIR', default=None,
                        help='write this run\'s logs to DIR (default: $ZROS_LOG_DIR or ~/.zros/log, '
                             'in a timestamped directory)')
    parser.add_argument('-d', '--debug', action='store_true', help='print the supervisor\'s debug messages')
    parser.add_argument('--router', action='store_true',
                        help='also run a Zenoh router (as `zros router`: tcp/0.0.0.0:7447) for the launch\'s '
                             'duration; the launch\'s processes connect to it, and --connect endpoints go to '
                             'the router (router to router)')
    from zros.config import add_session_options
    add_session_options(parser)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.formatter_class = argparse.RawDescriptionHelpFormatter
    parser.epilog = ('examples:\n  zros launch configs/talker_listener.launch.yaml topic:=news\n'
                     '  zros launch demo_nodes talker_listener.launch.py --print\n'
                     '  zros launch configs/talker_listener.launch.py --show-args')
    _add_options(parser)
    parser.add_argument('arguments', nargs=argparse.REMAINDER, metavar='[PKG] FILE [name:=value ...]',
                        help='a launch file (or a package and a file in it), then launch arguments')
    parser.set_defaults(handler=main)


def _late_options(items: list[str]) -> argparse.Namespace:
    """Options written after the file (`zros launch f.yaml --print`): argparse stops at the
    first positional, so the rest is parsed again here, options and items intermixed."""
    parser = argparse.ArgumentParser(prog='zros launch', add_help=False)
    _add_options(parser)
    parser.add_argument('items', nargs='*')
    return parser.parse_intermixed_args(items)


def _locate(items: list[str]) -> tuple[str, list[str]]:
    from zros.errors import CliError
    from zros.launch.packages import find_launch_file
    if not items:
        raise CliError('usage: zros launch [PKG] FILE [name:=value ...] (see zros launch -h)')
    first = items[0]
    if os.path.isfile(first):
        return first, items[1:]
    if ':=' not in first and len(items) > 1 and ':=' not in items[1]:
        return str(find_launch_file(first, items[1])), items[2:]
    raise CliError(f"no such launch file '{first}' (or give a package and a file: zros launch PKG FILE)")


def _show_arguments(path: str, launch_arguments: dict[str, str]) -> None:
    from zros.launch import declared_arguments
    arguments = declared_arguments(path, launch_arguments)
    print("Arguments (pass arguments as '<name>:=<value>'):")
    if not arguments:
        print('\n  No arguments.')
        return
    for argument in arguments:
        print(f"\n    '{argument.name}':" + ('*' if argument.conditional else ''))
        print('        ' + (argument.description.strip().replace('\n', '\n        ') or 'no description given'))
        if argument.choices:
            print(f"        Valid choices are: {', '.join(argument.choices)}")
        if argument.default is not None:
            print(f"        (default: '{argument.default}')")
        else:
            print('        (required)')
    if any(a.conditional for a in arguments):
        print('\n* argument(s) which are only used if specific conditions occur')


def _apply_session_options(early: argparse.Namespace, late: argparse.Namespace) -> list[str]:
    """Export the session options to the environment the supervisor and its children share.
    With --router, the --connect endpoints are the router's and are returned instead."""
    from zros.config import SESSION_OPTIONS, apply_session_options
    values = {}
    for option in SESSION_OPTIONS:
        dest = 'zros_' + option[2:].replace('-', '_')
        first, second = getattr(early, dest, None), getattr(late, dest, None)
        if isinstance(first, list) or isinstance(second, list):
            values[option] = (first or []) + (second or [])
        else:
            values[option] = second if second is not None else first
    router_links: list[str] = []
    if early.router or late.router:
        from zros.cli.router import DEFAULT_LISTEN, _endpoint_list
        router_links = _endpoint_list(values.get('--connect'), '--connect')
        values['--connect'] = ['tcp/127.0.0.1:' + DEFAULT_LISTEN.rpartition(':')[2]]
    if any(v not in (None, []) for v in values.values()):
        apply_session_options(values)
    return router_links


def _own_scripts_on_path() -> None:
    """Append the directory of this interpreter's scripts (`xacro`, `zros`) to PATH if missing.

    ROS 2 finds `xacro` in /opt/ros/<distro>/bin once sourced; zros installs it next to its own
    Python, which is not on PATH when a venv's `zros` is run without activating the venv. Last, so
    that the user's PATH still wins.
    """
    import sysconfig
    scripts = sysconfig.get_path('scripts')
    entries = os.environ.get('PATH', '').split(os.pathsep)
    if scripts and scripts not in entries:
        os.environ['PATH'] = os.pathsep.join([*filter(None, entries), scripts])


def main(args: argparse.Namespace) -> int:
    from zros.launch import LaunchError, parse_launch_arguments, resolve
    from zros.launch.launch_service import LaunchService
    from zros.launch.supervisor import make_log_dir
    late = _late_options(list(args.arguments))
    print_plan = args.print_plan or late.print_plan
    show_args = args.show_args or late.show_args
    debug = args.debug or late.debug
    log_dir_option = late.log_dir or args.log_dir
    router_links = _apply_session_options(args, late)
    _own_scripts_on_path()
    try:
        path, rest = _locate(late.items)
        launch_arguments = parse_launch_arguments(rest)
        if show_args:
            _show_arguments(path, launch_arguments)
            return 0
        log_dir = make_log_dir(log_dir_option)
        plan = resolve(path, launch_arguments=launch_arguments, log_dir=str(log_dir))
    except LaunchError as exc:
        print(str(exc), file=sys.stderr)
        return 1
    if print_plan:
        sys.stdout.write(plan.describe())
        return 0
    router = None
    if args.router or late.router:
        from zros.cli.router import Router
        router = Router(connect=router_links)
        for line in router.describe():
            print(f'[router] {line}', flush=True)
    try:
        return LaunchService.run_plan(plan, log_dir=log_dir, debug=debug)
    except LaunchError as exc:
        print(str(exc), file=sys.stderr)
        return 1
    finally:
        if router is not None:
            router.close()
