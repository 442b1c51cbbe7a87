"""`zros`: the command line (ros2cli's verbs and output formats).

Verb modules are imported only when their verb runs, so `zros node list` does not pay for
numpy or message classes. Every expected failure is a ZrosError (or CliError) and prints one
line to stderr with a non-zero exit: never a traceback.
"""
from __future__ import annotations

import argparse
import importlib
import sys

__all__ = ['main']

# verb -> (module, one-line help)
VERBS = {
    'run': ('zros.cli.run', 'Run an executable from a package (like ros2 run)'),
    'env': ('zros.cli.env', 'Print the exports that make a workspace\'s packages visible (eval "$(zros env WS)")'),
    'topic': ('zros.cli.topic', 'Inspect and publish topics'),
    'node': ('zros.cli.node', 'Inspect nodes'),
    'interface': ('zros.cli.interface', 'Show message, service and action definitions'),
    'service': ('zros.cli.service', 'Inspect and call services'),
    'param': ('zros.cli.param', 'Inspect and change node parameters'),
    'action': ('zros.cli.action', 'Inspect actions and send goals'),
    'view': ('zros.cli.view', 'The scene view in the browser (RViz, rqt_graph, rqt_console, images)'),
    'rqt': ('zros.cli.rqt', 'rqt in the browser: topic monitor, plot, service caller, parameters, graph, console'),
    'image': ('zros.cli.image', 'Save a frame of an image topic as PNG'),
    'tf': ('zros.cli.tf', 'Print the TF frame tree and its rates'),
    'lifecycle': ('zros.cli.lifecycle', 'Inspect and drive the lifecycle of managed nodes'),
    'launch': ('zros.cli.launch', 'Run a launch file (Python, YAML or XML)'),
    'test': ('zros.cli.test', 'Run a launch test file (like launch_test): its launch, then its tests'),
    'pkg': ('zros.cli.pkg', 'Create packages and find them (like ros2 pkg)'),
    'router': ('zros.cli.router', 'Run a Zenoh router for multi-machine set-ups'),
    'security': ('zros.cli.security', 'Create TLS keys and certificates (a CA and one per node)'),
    'bag': ('zros.cli.bag', 'Record and play back topics (MCAP files)'),
    'doctor': ('zros.cli.doctor', 'Check the zros set-up and the running system for problems'),
    'wtf': ('zros.cli.doctor', 'Alias of doctor (as ros2 wtf)'),
    'graph': ('zros.cli.graph', 'Print the node/topic graph as Graphviz DOT (or render SVG)'),
    'completion': ('zros.cli.completion', 'Print a bash or zsh completion script'),
    'port': ('zros.cli.port', 'Apply the rclpy -> zros porting edits to files or a package, show the diff'),
    'python': ('zros.cli.python', 'Run an unmodified ROS 2 Python program on zros'),
}
# Verbs that pass everything after their first argument to a program untouched.
PASSTHROUGH = {'run': 'zros.cli.run', 'python': 'zros.cli.python'}


class CliParser(argparse.ArgumentParser):
    """The parser of every verb and sub-verb (sub-parsers inherit their parent's class).

    ros2cli reads options anywhere among the positionals: the courses print
    `ros2 action send_goal /navigate_to_pose nav2_msgs/NavigateToPose --feedback "{pose: ...}"`.
    Plain argparse fills an optional positional (the goal) with its default as soon as the
    positionals before an option run out, and then rejects the goal as unrecognized; so a leaf
    parser (one without sub-verbs or a pass-through REMAINDER) reads options and positionals
    intermixed. Also, a negative number right after an option that takes a value is that
    option's value (argparse reads `--rate -1` as `--rate` followed by the option `-1`, and
    other negative numbers as unknown options), so the verb can say what is wrong with it.
    """

    _intermixing = False

    def parse_known_args(self, args=None, namespace=None):
        if args is not None:
            args = self._join_negative_values(list(args))
        if self._intermixing or not self._is_leaf():
            return super().parse_known_args(args, namespace)
        # parse_known_intermixed_args calls parse_known_args (this method) for each of its passes.
        self._intermixing = True
        try:
            return self.parse_known_intermixed_args(args, namespace)
        finally:
            self._intermixing = False

    def _is_leaf(self) -> bool:
        return not any(action.nargs in (argparse.PARSER, argparse.REMAINDER) for action in self._actions)

    def _join_negative_values(self, args: list[str]) -> list[str]:
        takes_value = {option for action in self._actions if action.option_strings and action.nargs is None
                       and not isinstance(action, (argparse._StoreConstAction, argparse._CountAction))
                       for option in action.option_strings}
        i = 0
        while i < len(args) - 1:
            if args[i] == '--':
                break
            if args[i] in takes_value and self._negative_number_matcher.match(args[i + 1]):
                longest = max(self._option_string_actions[args[i]].option_strings, key=len)
                args[i:i + 2] = [f'{longest}={args[i + 1]}']
            i += 1
        return args


def build_parser(verb: str | None = None) -> argparse.ArgumentParser:
    """The whole command line, or, given `verb`, one in which only that verb has its options:
    the other verbs' modules are not imported (a command's start is most of what `zros node
    list` costs, and the whole parser doubles it)."""
    parser = CliParser(
        prog='zros', description='zros: ROS 2 style tools on Zenoh. Run "zros <verb> -h" for help on a verb.')
    parser.add_argument('--version', action='store_true', help='print the zros version and exit')
    sub = parser.add_subparsers(dest='verb', metavar='<verb>')
    for name, (module, help_text) in VERBS.items():
        verb_parser = sub.add_parser(name, help=help_text, description=help_text)
        if verb is None or name == verb:
            importlib.import_module(module).add_arguments(verb_parser)
    return parser


def main(argv: list[str] | None = None) -> int:
    from zros.errors import ZrosError
    from zros.signals import exit_on_signals
    exit_on_signals()   # Ctrl-C and SIGTERM end every verb within a second, however it was started
    argv = list(sys.argv[1:] if argv is None else argv)
    if argv[:1] and argv[0] in PASSTHROUGH:
        # `zros run` and `zros python` pass what follows the program through, --ros-args included.
        try:
            return importlib.import_module(PASSTHROUGH[argv[0]]).main_passthrough(argv[1:])
        except ZrosError as exc:
            print(f'zros {argv[0]}: {exc}', file=sys.stderr)
            return 1
        except ImportError as exc:
            return _missing_extra(exc, ' '.join(['zros', *argv[:3]]))
    parser = build_parser(next((word for word in argv if not word.startswith('-')), None))
    args = parser.parse_args(argv)
    if args.version:
        from zros import __version__
        print(f'zros {__version__}')
        return 0
    if not args.verb:
        parser.print_help()
        return 0
    handler = getattr(args, 'handler', None)
    if handler is None:
        parser.parse_args([args.verb, '-h'])
        return 0
    try:
        return handler(args) or 0
    except KeyboardInterrupt:
        return 130
    except ZrosError as exc:
        print(f'zros {args.verb}: {exc}', file=sys.stderr)
        return 1
    except ImportError as exc:
        return _missing_extra(exc, f'zros {args.verb}')
    except BrokenPipeError:
        return 0


def _missing_extra(exc: ImportError, what: str) -> int:
    """Exit status 1 with the one-line error when an extra's package is missing (zros.extras);
    any other ImportError is a bug, and goes on as a traceback."""
    from zros.extras import missing_extra
    error = missing_extra(exc, what)
    if error is None:
        raise exc
    print(error, file=sys.stderr)
    return 1


def entry_point(argv: list[str] | None = None) -> None:
    """The `zros` command; with `argv`, a command that is a fixed zros command line (the
    `gzserver` and `gzclient` scripts are `zros run gazebo_ros gzserver ARGS...`)."""
    try:
        code = main(argv)
    except KeyboardInterrupt:   # Ctrl-C before a verb's own handling (while importing, say)
        code = 130
    from zros.context import exit_process
    exit_process(code if isinstance(code, int) else 0)


if __name__ == '__main__':
    entry_point()
