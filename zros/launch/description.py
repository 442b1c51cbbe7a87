"""From a launch file to a `Plan`: parse, then resolve every action in order.

`resolve()` is what `zros launch` (and `--print`) run before anything starts: it evaluates
conditions and substitutions, follows includes, and collects the processes with their final
command lines. `declared_arguments()` is the static walk behind `--show-args`.
"""
from __future__ import annotations

import os
from typing import Any

from zros.launch.actions import Action, registered_tags
from zros.launch.actions.arg import DeclareArgument
from zros.launch.actions.include import Include, parse_launch_file
from zros.launch.context import DeclaredArgument, LaunchContext
from zros.launch.errors import LaunchError
from zros.launch.plan import Plan

__all__ = ['resolve', 'declared_arguments', 'parse_launch_file', 'BUILTIN_CONFIGURATIONS',
           'parse_launch_arguments']

#: Launch configurations that mean something without an `arg` tag (as in ROS 2's launch).
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


def _walk(actions: list[Action], context: Any) -> None:
    """Visit actions depth-first in file order; `execute` returns what to visit next."""
    stack = list(reversed(actions))
    while stack:
        action = stack.pop()
        stack.extend(reversed(action.visit(context)))


def resolve(path: str, *, launch_arguments: dict[str, str] | None = None,
            environment: dict[str, str] | None = None, log_dir: str = '') -> Plan:
    """Resolve a launch file into a Plan; LaunchFileError (`file:line: tag: key: reason`) for
    any problem, before anything is started."""
    registered_tags()
    path = os.path.normpath(str(path))
    launch_arguments = dict(launch_arguments or {})
    actions = parse_launch_file(path)
    context = LaunchContext(launch_arguments=launch_arguments, environment=environment, log_dir=log_dir)
    context.known_arguments = {arg.name: arg for arg in declared_arguments(path, launch_arguments, actions=actions)}
    context.enter_file(path, None)
    _walk(actions, context)
    context.leave_file()
    known = set(context.declared) | set(context.known_arguments) | set(BUILTIN_CONFIGURATIONS)
    unknown = [name for name in launch_arguments if name not in known]
    if unknown:
        declared = ', '.join(context.declared_names()) or 'none'
        raise LaunchError(f"{path}: unknown launch argument '{unknown[0]}' (declared arguments: {declared})")
    arguments = {name: context.configurations.get(name, '') for name in context.declared}
    return Plan(path, context.effects, arguments=arguments, declared=dict(context.declared), log_dir=log_dir)


def declared_arguments(path: str, launch_arguments: dict[str, str] | None = None, *,
                       actions: list[Action] | None = None) -> list[DeclaredArgument]:
    """Every `arg` of a file and of the files it includes, without running anything.

    Includes are followed when their path can be evaluated from the defaults seen so far;
    arguments under an `if`/`unless` are marked `conditional` (ros2 launch shows them with '*').
    """
    registered_tags()
    found: dict[str, DeclaredArgument] = {}
    context = LaunchContext(launch_arguments=launch_arguments or {})
    seen_files: set[str] = set()

    def walk(items: list[Action], conditional: bool) -> None:
        for action in items:
            cond = conditional or action.condition is not None
            if isinstance(action, DeclareArgument):
                found.setdefault(action.name, action.declaration(conditional=cond))
                if action.name not in context.configurations and action.default is not None:
                    try:
                        context.configurations[action.name] = action.default.perform(context)
                    except LaunchError:
                        pass
            elif isinstance(action, Include):
                try:
                    included = action.resolve_path(context)
                    real = os.path.realpath(included)
                    if real in seen_files or not os.path.isfile(included):
                        continue
                    seen_files.add(real)
                    child_actions = parse_launch_file(included)
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
    walk(parse_launch_file(path) if actions is None else actions, False)
    return list(found.values())
