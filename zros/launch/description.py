"""From a launch file (Python, YAML or XML) to a `Plan`: load, then resolve every action in order.

`resolve()` is what `zros launch` (and `--print`) run before anything starts: it evaluates
conditions and substitutions, follows includes, and collects the processes with their final
command lines. `declared_arguments()` is the static walk behind `--show-args`.
"""
from __future__ import annotations

import os
from typing import Any, Callable

from zros.launch.action import registered_tags
from zros.launch.context import DeclaredArgument, LaunchContext
from zros.launch.errors import LaunchError, LaunchFileError, Origin
from zros.launch.files import load_launch_file
from zros.launch.plan import LogMessage, Plan

__all__ = ['resolve', 'resolve_actions', 'walk', 'declared_arguments', 'load_launch_file', 'BUILTIN_CONFIGURATIONS',
           'parse_launch_arguments', 'Deferred']

#: Launch configurations that mean something without an argument (as in ROS 2's launch).
BUILTIN_CONFIGURATIONS = ('sigterm_timeout', 'sigkill_timeout', 'launch-prefix')


def parse_launch_arguments(items: list[str]) -> dict[str, str]:
    """`name:=value` items from the command line; the last one of a name wins."""
    values: dict[str, str] = {}
    for item in items:
        name, sep, value = item.partition(':=')
        if not sep or not name:
            raise LaunchError(f"launch arguments look like name:=value, got '{item}'")
        values[name] = value
    return values


def walk(actions: list, context: Any) -> None:
    """Visit actions depth-first in file order; `visit` returns what to visit next."""
    stack = list(reversed(actions))
    while stack:
        action = stack.pop()
        stack.extend(reversed(action.visit(context) or []))


def resolve(path: str, *, launch_arguments: dict[str, str] | None = None,
            environment: dict[str, str] | None = None, log_dir: str = '') -> Plan:
    """Resolve a launch file into a Plan; LaunchFileError (`file:line: tag: key: reason`) for
    any problem, before anything is started.

    A command-line argument must be declared (DeclareLaunchArgument / `arg`) or read by the
    launch (`LaunchConfiguration` / `$(var)`, as ROS 2 launch files often read undeclared ones
    with a default); anything else is reported as a typo.
    """
    path = os.path.normpath(str(path))
    return resolve_actions(load_launch_file(path), path, launch_arguments=launch_arguments,
                           environment=environment, log_dir=log_dir)


#: Launch arguments a launch file read from the command line itself while it was loaded
#: (nav2_common's ParseMultiRobotPose reads `robots:=` from sys.argv): known, not typos.
_READ_FROM_COMMAND_LINE: set[str] = set()


def note_command_line_read(name: str) -> None:
    """Record that the launch file read launch argument `name` from the command line."""
    _READ_FROM_COMMAND_LINE.add(name)


def resolve_actions(actions: list, path: str, *, launch_arguments: dict[str, str] | None = None,
                    environment: dict[str, str] | None = None, log_dir: str = '') -> Plan:
    """`resolve()` for actions already loaded from `path` (a launch test's
    `generate_test_description()` gives them); the same checks, the same Plan."""
    registered_tags()
    launch_arguments = dict(launch_arguments or {})
    context = LaunchContext(launch_arguments=launch_arguments, environment=environment, log_dir=log_dir)
    context.known_arguments = {arg.name: arg for arg in declared_arguments(path, launch_arguments, actions=actions)}
    context.enter_file(path, None)
    level = context.begin_capture()
    walk(actions, context)
    effects = context.end_capture(level)
    context.leave_file()
    known = (set(context.declared) | set(context.known_arguments) | context.read_configurations
             | set(BUILTIN_CONFIGURATIONS) | _READ_FROM_COMMAND_LINE)
    unknown = [name for name in launch_arguments if name not in known]
    if unknown:
        declared = ', '.join(context.declared_names()) or 'none'
        raise LaunchError(f"{path}: unknown launch argument '{unknown[0]}' (declared arguments: {declared})")
    arguments = {name: context.configurations.get(name, '') for name in context.declared}
    return Plan(path, effects, arguments=arguments, declared=dict(context.declared), log_dir=log_dir,
                context=context)


def declared_arguments(path: str, launch_arguments: dict[str, str] | None = None, *,
                       actions: list | None = None) -> list[DeclaredArgument]:
    """Every declared argument of a file and of the files it includes, without running anything.

    Includes are followed when their path can be evaluated from the defaults seen so far;
    arguments under a condition are marked `conditional` (ros2 launch shows them with '*').
    """
    from zros.launch.actions.arg import DeclareLaunchArgument
    from zros.launch.actions.include import IncludeLaunchDescription
    registered_tags()
    found: dict[str, DeclaredArgument] = {}
    context = LaunchContext(launch_arguments=launch_arguments or {})
    seen_files: set[str] = set()

    def walk(items: list, conditional: bool) -> None:
        for action in items:
            cond = conditional or action.condition is not None
            if isinstance(action, DeclareLaunchArgument):
                found.setdefault(action.name, action.declaration(conditional=cond))
                if action.name not in context.configurations and action.default is not None:
                    try:
                        context.configurations[action.name] = action.default.perform(context)
                    except LaunchError:
                        pass
            elif isinstance(action, IncludeLaunchDescription):
                try:
                    included = action.resolve_path(context)
                    real = os.path.realpath(included)
                    if real in seen_files or not os.path.isfile(included):
                        continue
                    seen_files.add(real)
                    child_actions = action.load(included)
                except LaunchError:
                    continue
                context.enter_file(included, None)
                try:
                    walk(child_actions, cond)
                finally:
                    context.leave_file()
            else:
                walk(action.sub_actions(), cond)

    path = os.path.normpath(str(path))
    seen_files.add(os.path.realpath(path))
    context.enter_file(path, None)
    walk(load_launch_file(path) if actions is None else actions, False)
    return list(found.values())


class Deferred:
    """An event handler function, resolved when its event happens: `f(event, context)` returns
    actions, which are resolved in a copy of the context taken where the handler was
    registered. A failure is reported as an ERROR line of the launch, never a traceback."""

    def __init__(self, function: Callable, context: LaunchContext, origin: Origin) -> None:
        self.function, self.context, self.origin = function, context, origin

    def __str__(self) -> str:
        return f"{getattr(self.function, '__name__', 'function')}() at {self.origin.path}:{self.origin.line}"

    def __call__(self, event: Any) -> list:
        from zros.launch.actions.group import check_actions
        from zros.launch.actions.opaque import call_user_function
        context = self.context.snapshot()
        level = context.begin_capture()
        try:
            result = call_user_function(self.function, self.origin, event, context)
            walk(check_actions(result, self.origin), context)
        except LaunchFileError as exc:
            return [LogMessage('ERROR', str(exc), self.origin)]
        return context.end_capture(level)
