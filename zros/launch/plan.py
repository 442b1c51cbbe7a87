"""The resolved launch: what will happen, in order, with every substitution already evaluated.

Resolution turns a launch file into a `Plan` of effects; the supervisor carries the plan out
and `zros launch --print` shows it. Keeping the two apart is what lets a launch validate every
node (packages, executables, names, parameter files) before it starts any process.
"""
from __future__ import annotations

import shlex
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, NamedTuple, Union

import yaml

from zros.launch.context import DeclaredArgument
from zros.launch.errors import Origin

__all__ = ['ParamsFile', 'GeneratedParams', 'NodeInfo', 'ProcessSpec', 'LogMessage', 'TimerEffect',
           'ShutdownEffect', 'EventHandlerEffect', 'CallEffect', 'TaskEffect', 'ChangeStateEffect', 'Effect', 'Plan',
           'OUTPUT_MODES']

OUTPUT_MODES = ('log', 'screen', 'both', 'own_log')


class ParamsFile(NamedTuple):
    """A parameter file written by the user, passed as `--params-file` unchanged."""

    path: str


class GeneratedParams(NamedTuple):
    """Parameters written in the launch file: a ROS-layout document the supervisor writes to
    `<log dir>/params/<process>.yaml` and passes as `--params-file`."""

    document: dict

    def to_yaml(self) -> str:
        return yaml.safe_dump(self.document, default_flow_style=False, sort_keys=False)


class NodeInfo(NamedTuple):
    package: str
    executable: str
    name: str | None          # the node name set with `name:` (None: the node's own)
    namespace: str            # '/' when none

    def display_name(self) -> str:
        name = self.name or f'<{self.executable}>'
        return f"{'' if self.namespace == '/' else self.namespace}/{name}"


@dataclass(frozen=True)
class ProcessSpec:
    """One process to start: `cmd_head + --params-file ...`, fully resolved.

    `label` is the name in output prefixes without the counter (`talker` -> `[talker-1]`).
    """

    label: str
    cmd_head: tuple[str, ...]
    params: tuple[Union[ParamsFile, GeneratedParams], ...] = ()
    env: tuple[tuple[str, str | None], ...] = ()   # changes to the supervisor's environment
    cwd: str | None = None
    shell_text: str | None = None                   # the command line as written, for `shell: true`
    output: str = 'log'
    respawn: bool = False
    respawn_delay: float = 0.0
    respawn_max_retries: int = -1
    sigterm_timeout: float = 5.0
    sigkill_timeout: float = 5.0
    on_exit_shutdown: bool = False
    emulate_tty: bool = False                       # stdout and stderr are pseudo-terminals
    origin: Origin | None = None
    node: NodeInfo | None = None
    lifecycle: bool = False                         # started by a LifecycleNode action
    source: Any = field(default=None, compare=False, repr=False)   # the action that made it

    def command(self, params_paths: list[str]) -> list[str]:
        """The argv, given where each GeneratedParams entry was written."""
        middle: list[str] = []
        for path in params_paths:
            middle += ['--params-file', path]
        return [*self.cmd_head, *middle]

    def generated_params_paths(self, directory: Path, process_name: str) -> list[str]:
        """Where the supervisor writes this process's parameter files (and --print shows)."""
        paths, generated = [], 0
        for source in self.params:
            if isinstance(source, ParamsFile):
                paths.append(source.path)
            else:
                generated += 1
                suffix = '' if generated == 1 else f'-{generated}'
                paths.append(str(directory / f'{process_name}{suffix}.yaml'))
        return paths


class LogMessage(NamedTuple):
    level: str            # DEBUG, INFO, WARNING, ERROR
    message: str
    origin: Origin | None = None
    logger: str = 'launch.user'   # the name in the line's prefix, as launch's logger names


class TimerEffect(NamedTuple):
    """`effects`, carried out `period` seconds [s] after the timer starts. A timer with
    `cancel_on_shutdown` False still fires while the launch shuts down; then only its log lines
    and shutdowns are carried out. `sim_time` (a ROSTimer's) answers, when the timer starts,
    whether the launch's ROS time is sim time: then the period is counted on /clock
    (zros.launch.ros_time) instead of the wall clock."""

    period: float
    effects: list
    origin: Origin | None = None
    cancel_on_shutdown: bool = True
    sim_time: Callable[[], bool] | None = None


class ShutdownEffect(NamedTuple):
    """End the launch here. `sigint_delivered`: the Shutdown event said a SIGINT already reached
    the processes (`due_to_sigint` in an interactive launch), so they are not sent another."""

    reason: str
    origin: Origin | None = None
    sigint_delivered: bool = False


class CallEffect(NamedTuple):
    """A function the supervisor calls when the launch reaches this point, after starting the
    processes before it (launch_testing's ReadyToTest). It runs on the supervisor's thread and
    must return at once."""

    label: str                 # what `--print` shows: 'ready to test'
    function: Any
    origin: Origin | None = None


class TaskEffect(NamedTuple):
    """Work that waits on something outside the launch (a component container's service), so
    it runs on a thread of its own while the supervisor keeps watching its processes; the launch
    is not done before it returns. `function(stop)` gets a threading.Event set when the launch
    shuts down (it should then return soon) and returns the effects to carry out, on the
    supervisor's thread, once it is done; a LaunchError it raises fails the launch (its message
    logged, exit code 1)."""

    label: str                 # what `--print` shows
    function: Any
    origin: Origin | None = None


class ChangeStateEffect(NamedTuple):
    """Ask the lifecycle nodes of the launch that `matcher` picks, among those running at this
    point, for a transition (launch_ros's ChangeState event). The supervisor runs it as
    `zros lifecycle set` (zros.launch.lifecycle)."""

    matcher: Any               # called with a LifecycleNode action
    transition_id: int
    label: str                 # 'configure'
    origin: Origin | None = None

    def matches(self, spec: 'ProcessSpec') -> bool:
        return spec.lifecycle and bool(self.matcher(spec.source))


class EventHandlerEffect(NamedTuple):
    """Effects to carry out when a process starts or exits (OnProcessStart / OnProcessExit),
    or a lifecycle node of the launch goes through a transition it requested (OnStateTransition).

    `target` is the action whose processes it watches (None: every process). `effects` were
    resolved with the launch; `deferred`, when set, is a handler function resolved only when
    the event happens (`deferred(event) -> effects`). `transition` (a StateTransitionFilter)
    says which lifecycle steps a 'transition' handler fires on.
    """

    event: str                 # 'start', 'exit', 'shutdown' or 'transition'
    target: Any
    effects: list
    deferred: Any = None
    origin: Origin | None = None
    transition: Any = None

    def matches(self, spec: 'ProcessSpec') -> bool:
        from zros.launch.event_handlers.on_action_event_base import target_matches
        return target_matches(self.target, spec.source)

    def effects_for(self, process_name: str, pid: int, returncode: int | None, cmd: list) -> list:
        """What to do for this event (the supervisor calls it when the event happens)."""
        if self.deferred is None:
            return self.effects
        from zros.launch.events.process import ProcessExited, ProcessStarted
        common = dict(action=self.target, name=process_name, cmd=list(cmd), cwd=None, env=None, pid=pid)
        event = ProcessStarted(**common) if returncode is None else ProcessExited(returncode=returncode, **common)
        return self.deferred(event)

    def effects_at_shutdown(self, reason: str) -> list:
        """What an OnShutdown handler does (its function receives launch.events.Shutdown)."""
        if self.deferred is None:
            return self.effects
        from zros.launch.events import Shutdown
        return self.deferred(Shutdown(reason=reason))


Effect = Union[ProcessSpec, LogMessage, TimerEffect, ShutdownEffect, EventHandlerEffect, CallEffect, TaskEffect,
               ChangeStateEffect]


@dataclass
class Plan:
    """Everything a launch file resolved to."""

    launch_file: str
    effects: list = field(default_factory=list)
    arguments: dict[str, str] = field(default_factory=dict)          # final values of declared args
    declared: dict[str, DeclaredArgument] = field(default_factory=dict)
    log_dir: str = ''
    # The context the file was resolved in: the launch.EventHandlers it registered stay on its
    # event queue while the plan runs (zros.launch.launch_service).
    context: Any = field(default=None, repr=False, compare=False)

    def processes_in_start_order(self) -> list[tuple[float, ProcessSpec]]:
        """(start delay, spec) in the order the supervisor starts them (timers by due time)."""
        out: list[tuple[float, ProcessSpec]] = []
        pending: list[tuple[float, int, list]] = [(0.0, 0, self.effects)]
        counter = 1
        while pending:
            pending.sort(key=lambda item: (item[0], item[1]))
            when, _, effects = pending.pop(0)
            for effect in effects:
                if isinstance(effect, ProcessSpec):
                    out.append((when, effect))
                elif isinstance(effect, TimerEffect):
                    pending.append((when + effect.period, counter, effect.effects))
                    counter += 1
                elif isinstance(effect, ShutdownEffect):
                    return out
        return out

    def describe(self) -> str:
        """The plan as `zros launch --print` shows it."""
        lines = [f'launch file: {self.launch_file}']
        if self.arguments:
            lines.append('arguments:')
            lines += [f'  {name}:={value}' for name, value in self.arguments.items()]
        lines.append(f'log directory: {self.log_dir}')
        numbers: dict[int, str] = {}
        for index, (_, spec) in enumerate(self.processes_in_start_order(), start=1):
            numbers.setdefault(id(spec), f'{spec.label}-{index}')
        lines.append('')
        self._describe_effects(self.effects, lines, numbers, indent='')
        return '\n'.join(lines).rstrip() + '\n'

    def _describe_effects(self, effects: list, lines: list[str], numbers: dict, indent: str) -> None:
        for effect in effects:
            if isinstance(effect, ProcessSpec):
                self._describe_process(effect, lines, numbers.get(id(effect), effect.label), indent)
            elif isinstance(effect, LogMessage):
                lines.append(f'{indent}log [{effect.level}]: {effect.message}')
            elif isinstance(effect, TimerEffect):
                lines.append(f'{indent}after {effect.period:g} s:')
                self._describe_effects(effect.effects, lines, numbers, indent + '  ')
            elif isinstance(effect, ShutdownEffect):
                lines.append(f'{indent}shutdown' + (f': {effect.reason}' if effect.reason else ''))
            elif isinstance(effect, (CallEffect, TaskEffect)):
                lines.append(f'{indent}{effect.label}')
            elif isinstance(effect, ChangeStateEffect):
                lines.append(f'{indent}change state of {self._targets(effect, numbers, "a lifecycle node")}: '
                             f'{effect.label} [{effect.transition_id}]')
            elif isinstance(effect, EventHandlerEffect):
                if effect.event == 'shutdown':
                    lines.append(f'{indent}on shutdown:')
                elif effect.event == 'transition':
                    lines.append(f'{indent}on state transition {effect.transition.describe()} of '
                                 f'{self._targets(effect, numbers, "any lifecycle node")}:')
                else:
                    lines.append(f'{indent}on {effect.event} of {self._targets(effect, numbers)}:')
                if effect.deferred is not None:
                    lines.append(f'{indent}  (actions from {effect.deferred}, resolved then)')
                self._describe_effects(effect.effects, lines, numbers, indent + '  ')

    def _targets(self, effect: EventHandlerEffect | ChangeStateEffect, numbers: dict, anyone: str = 'any process') -> str:
        """The processes an event handler watches, or a ChangeState reaches, by name."""
        if isinstance(effect, EventHandlerEffect) and effect.target is None:
            return anyone
        names = [numbers.get(id(spec), spec.label) for spec in self._all_processes(self.effects)
                 if effect.matches(spec)]
        return ', '.join(f'[{name}]' for name in names) or 'a process that is never started'

    def _all_processes(self, effects: list) -> list[ProcessSpec]:
        found = []
        for effect in effects:
            if isinstance(effect, ProcessSpec):
                found.append(effect)
            elif isinstance(effect, (TimerEffect, EventHandlerEffect)):
                found += self._all_processes(effect.effects)
        return found

    def _describe_process(self, spec: ProcessSpec, lines: list[str], name: str, indent: str) -> None:
        where = f'  ({spec.origin.path}:{spec.origin.line})' if spec.origin else ''
        lines.append(f'{indent}process [{name}]{where}')
        sub = indent + '    '
        if spec.node is not None:
            where = (f'package {spec.node.package}, executable {spec.node.executable}' if spec.node.package
                     else f'executable {spec.node.executable} from PATH')
            lines.append(f'{sub}node: {spec.node.display_name()}  ({where})')
        paths = spec.generated_params_paths(Path(self.log_dir) / 'params', name)
        cmd = spec.shell_text if spec.shell_text is not None else shlex.join(spec.command(paths))
        lines.append(f'{sub}cmd: {cmd}' + ('   (run by /bin/sh)' if spec.shell_text is not None else ''))
        if spec.cwd:
            lines.append(f'{sub}cwd: {spec.cwd}')
        if spec.env:
            changes = [f'{k}={v}' if v is not None else f'unset {k}' for k, v in spec.env]
            lines.append(f'{sub}env: ' + ', '.join(changes))
        for source, path in zip(spec.params, paths):
            if isinstance(source, GeneratedParams):
                lines.append(f'{sub}params ({path}):')
                lines += [f'{sub}  {line}' for line in source.to_yaml().rstrip().splitlines()]
        options = [f'output: {spec.output}']
        if spec.respawn:
            retries = 'forever' if spec.respawn_max_retries < 0 else f'max {spec.respawn_max_retries} retries'
            options.append(f'respawn after {spec.respawn_delay:g} s ({retries})')
        if spec.on_exit_shutdown:
            options.append('on exit: shutdown')
        options.append(f'sigterm after {spec.sigterm_timeout:g} s, sigkill {spec.sigkill_timeout:g} s later')
        lines.append(f'{sub}' + '; '.join(options))

