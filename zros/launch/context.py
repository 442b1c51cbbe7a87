"""The state a launch file is resolved in: launch configurations, environment, ROS scope.

Resolution walks the parsed actions in order (`zros.launch.description.resolve`); actions read
and change this context and add effects (processes to start, messages to log, timers) to the
plan. Groups push and pop scopes, includes push and pop the current file, timers capture their
children's effects. Nothing here starts a process or touches the file system.
"""
from __future__ import annotations

import copy
import os
from collections import Counter
from collections.abc import Iterable, Iterator, MutableMapping
from typing import Any, NamedTuple

from zros.launch.errors import LaunchFileError, Origin
from zros.launch.locals import LaunchLocals, pop_saved
from zros.launch.event_dispatch import EventDispatch
from zros.launch.template import make_anon_name

__all__ = ['LaunchContext', 'RosScope', 'DeclaredArgument']


class RosScope:
    """launch_ros's scope, kept where launch_ros keeps it: in the launch configurations, as
    `ros_namespace` (the pushed namespace), `global_params` (`(name, value)` pairs, or parameter
    file paths, for every later node) and `ros_remaps` (`(from, to)` pairs). Saving, restoring
    and resetting configurations (groups, includes, ResetLaunchConfigurations) therefore covers
    it, and code written against launch_ros reads the same keys.

    Args:
        configurations: the launch configurations to read and write (a LaunchContext's, or
            those of any context that has `launch_configurations`).

    A saved scope shares its lists with the current one, so lists are replaced, never changed
    in place.
    """

    NAMESPACE = 'ros_namespace'
    PARAMS = 'global_params'
    REMAPS = 'ros_remaps'

    def __init__(self, configurations: MutableMapping[str, Any]) -> None:
        self._configurations = configurations

    @classmethod
    def of(cls, context: Any) -> 'RosScope':
        """The scope of a LaunchContext, or of any object with `launch_configurations`."""
        configurations = context.configurations if isinstance(context, LaunchContext) else context.launch_configurations
        return cls(configurations)

    @property
    def namespace(self) -> str:
        """The pushed namespace ('' when none was pushed)."""
        return self._configurations.get(self.NAMESPACE) or ''

    @namespace.setter
    def namespace(self, value: str) -> None:
        self._configurations[self.NAMESPACE] = value

    @property
    def params(self) -> list[Any]:
        return list(self._configurations.get(self.PARAMS) or [])

    @property
    def param_pairs(self) -> list[tuple[str, Any]]:
        """The `(name, value)` pairs of `params` (without the parameter files)."""
        return [item for item in self.params if isinstance(item, tuple)]

    @property
    def remaps(self) -> list[tuple[str, str]]:
        return list(self._configurations.get(self.REMAPS) or [])

    def add_param(self, item: Any) -> None:
        """A `(name, value)` pair or a parameter file path, for every later node in the scope."""
        self._configurations[self.PARAMS] = [*self.params, item]

    def add_remap(self, source: str, target: str) -> None:
        self._configurations[self.REMAPS] = [*self.remaps, (source, target)]


class DeclaredArgument(NamedTuple):
    """An `arg` tag, as `--show-args` and the error messages list it."""

    name: str
    default: str | None            # the default as written (substitutions not evaluated)
    description: str
    choices: tuple[str, ...]
    origin: Origin
    conditional: bool = False      # inside an if/unless (may not be declared at all)


class LaunchContext(EventDispatch):
    """Mutable resolution state; one per `resolve()` call.

    Args:
        argv: the command line's extra arguments, kept for the entities that read them.
        noninteractive: True when no terminal is attached (launch's flag, kept for user code).
        launch_arguments: `name:=value` pairs from the command line (set as configurations
            before the file is read, as ros2 launch does).
        environment: the environment the launch starts from (default: os.environ).
        log_dir: this run's log directory (for `$(log_dir)` and generated parameter files).
    """

    def __init__(self, *, argv: Iterable[str] | None = None, noninteractive: bool = False,
                 launch_arguments: dict[str, str] | None = None,
                 environment: dict[str, str] | None = None, log_dir: str = '') -> None:
        super().__init__()
        self.argv = list(argv or [])
        self.noninteractive = noninteractive
        self.is_shutdown = False
        self._locals = LaunchLocals()
        self.launch_arguments = dict(launch_arguments or {})
        self.configurations: dict[str, str] = dict(self.launch_arguments)
        self.base_environment = dict(os.environ if environment is None else environment)
        self.environment: dict[str, str] = dict(self.base_environment)
        self.log_dir = log_dir
        self.declared: dict[str, DeclaredArgument] = {}
        self.known_arguments: dict[str, DeclaredArgument] = {}   # from a static walk, for messages
        self._saved_configurations: list[dict[str, Any]] = []
        self._saved_environments: list[dict[str, str]] = []
        self._files: list[tuple[str, Origin | None]] = []
        self._captures: list[list] = [[]]
        self._anon: dict[str, str] = {}
        self.read_configurations: set[str] = set()   # names substitutions looked up
        # nodes started per fully qualified name (launch_ros.utilities.track_node_names), shared
        # with snapshots: a duplicate name anywhere in the launch is one to warn about
        self.node_names: Counter[str] = Counter()
        # fully qualified names of the component containers this launch starts: a
        # LoadComposableNodes aimed at one runs its nodes as processes (zros.launch.actions.composable)
        self.containers: set[str] = set()
        self._asyncio_loop: Any = None
        # SetUseSimTime: the launch's ROS time (ROSTimer's) follows /clock
        self.launch_use_sim_time = False

    # -- the asyncio loop a launch runs in (launch.LaunchContext.asyncio_loop) -----------------
    @property
    def asyncio_loop(self) -> Any:
        """The asyncio loop of `LaunchService.run_async()` while it runs the launch, else None:
        zros's launch runs on the supervisor's thread and needs no loop of its own."""
        return self._asyncio_loop

    def _set_asyncio_loop(self, loop: Any) -> None:
        self._asyncio_loop = loop

    @property
    def ros(self) -> RosScope:
        """launch_ros's scope (namespace, parameters, remappings), a view of the configurations."""
        return RosScope(self.configurations)

    # -- what Python launch code sees (launch.LaunchContext) -----------------------------------
    @property
    def launch_configurations(self) -> MutableMapping[str, str]:
        """The launch configurations, readable and writable (as in launch); reads are recorded
        like `$(var)`'s, so an argument only a Python function reads is still a known one."""
        return _RecordingConfigurations(self)

    def perform_substitution(self, substitution: Any) -> str:
        from zros.launch.template import perform, to_template
        return perform(to_template(substitution), self)

    def note_configuration_read(self, name: str) -> None:
        self.read_configurations.add(name)

    def snapshot(self) -> 'LaunchContext':
        """A copy to resolve more actions in later (an event handler function), sharing the
        anonymous names and the record of configurations read."""
        copied = copy.copy(self)
        copied.configurations = dict(self.configurations)
        copied.environment = dict(self.environment)
        copied._saved_configurations = list(self._saved_configurations)
        copied._saved_environments = list(self._saved_environments)
        copied._locals = self._locals.copy()
        copied._files = list(self._files)
        copied._captures = [[]]
        return copied

    # -- files (for $(dirname), $(filename) and include cycles) --------------------------------
    @property
    def current_file(self) -> str:
        return self._files[-1][0] if self._files else ''

    @property
    def file_stack(self) -> list[str]:
        return [path for path, _ in self._files]

    def enter_file(self, path: str, origin: Origin | None) -> None:
        real = os.path.realpath(path)
        stack = [os.path.realpath(p) for p in self.file_stack]
        if real in stack:
            chain = ' -> '.join([*self.file_stack[stack.index(real):], path])
            raise LaunchFileError(origin, f'include cycle: {chain}')
        self._files.append((path, origin))

    def leave_file(self) -> None:
        self._files.pop()

    # -- scopes: the stacks that Push/Pop/Reset actions work on ------------------------------
    def push_launch_configurations(self) -> None:
        self._saved_configurations.append(dict(self.configurations))

    def pop_launch_configurations(self) -> None:
        self.configurations = pop_saved(self._saved_configurations, 'PopLaunchConfigurations',
                                        'PushLaunchConfigurations')

    def push_environment(self) -> None:
        self._saved_environments.append(dict(self.environment))

    def pop_environment(self) -> None:
        self.environment = pop_saved(self._saved_environments, 'PopEnvironment', 'PushEnvironment')

    def reset_environment(self) -> None:
        """Back to the environment the launch started from."""
        self.environment = dict(self.base_environment)

    def reset_configurations(self, keep: dict[str, str]) -> None:
        """`ResetLaunchConfigurations`: only `keep` remains (the ROS scope too is gone)."""
        self.configurations = dict(keep)

    # launch's names for the same steps (its LaunchService and tests call these)
    _push_launch_configurations = push_launch_configurations
    _pop_launch_configurations = pop_launch_configurations
    _push_environment = push_environment
    _pop_environment = pop_environment
    _reset_environment = reset_environment

    # -- locals: the names an event handler's actions see (`context.locals.event`) --------------
    @property
    def locals(self) -> Any:  # noqa: A003 - launch's name
        """The locals as read-only attributes (`context.locals.event`)."""
        return self._locals.view()

    def extend_locals(self, extensions: dict[str, Any]) -> None:
        self._locals.extend(extensions)

    def extend_globals(self, extensions: dict[str, Any]) -> None:
        self._locals.extend_globals(extensions)

    def get_locals_as_dict(self) -> dict[str, Any]:
        return self._locals.as_dict()

    def _push_locals(self) -> None:
        self._locals.push()

    def _pop_locals(self) -> None:
        self._locals.pop()

    # -- effects -------------------------------------------------------------------------------
    def emit(self, effect: Any) -> None:
        self._captures[-1].append(effect)

    def begin_capture(self) -> int:
        """Collect the effects emitted from now on apart; returns the capture's level."""
        self._captures.append([])
        return len(self._captures) - 1

    def end_capture(self, level: int | None = None) -> list:
        """The effects collected since the last `begin_capture()` (or since the one that
        returned `level`, closing any capture left open inside it: an action that user code
        executed by hand, without visiting what it returned)."""
        if level is None:
            return self._captures.pop()
        captured = self._captures[level]
        del self._captures[level:]
        return captured

    @property
    def collecting_effects(self) -> bool:
        """Whether the effects emitted now are collected to be carried out (a launch being
        resolved or run, a timer's or a handler's actions); not on a context that code uses
        directly (`Shutdown().visit(LaunchContext())`), where only events reach anyone."""
        return len(self._captures) > 1

    @property
    def effects(self) -> list:
        return self._captures[0]

    # -- helpers -------------------------------------------------------------------------------
    def anon_name(self, name: str) -> str:
        if name not in self._anon:
            self._anon[name] = make_anon_name(name)
        return self._anon[name]

    def environment_changes(self) -> dict[str, str | None]:
        """Variables that differ from the starting environment (None: unset)."""
        changes: dict[str, str | None] = {}
        for name, value in self.environment.items():
            if self.base_environment.get(name) != value:
                changes[name] = value
        for name in self.base_environment:
            if name not in self.environment:
                changes[name] = None
        return changes

    def declared_names(self) -> list[str]:
        return sorted(set(self.declared) | set(self.known_arguments))


class _RecordingConfigurations(MutableMapping):
    """`context.launch_configurations`: the context's configurations, noting each name read."""

    def __init__(self, context: LaunchContext) -> None:
        self._context = context

    def __getitem__(self, name: str) -> str:
        self._context.note_configuration_read(name)
        return self._context.configurations[name]

    def __contains__(self, name: object) -> bool:
        if isinstance(name, str):
            self._context.note_configuration_read(name)
        return name in self._context.configurations

    def __setitem__(self, name: str, value: str) -> None:
        self._context.configurations[name] = value

    def __delitem__(self, name: str) -> None:
        del self._context.configurations[name]

    def __iter__(self) -> Iterator[str]:
        return iter(self._context.configurations)

    def __len__(self) -> int:
        return len(self._context.configurations)
