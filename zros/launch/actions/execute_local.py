"""`ExecuteLocal` (launch.actions.ExecuteLocal): run a described executable as a supervised local
process. ExecuteProcess and launch_ros's Node are ExecuteLocal with the description built from
their own arguments; all three resolve to one ProcessSpec that the supervisor starts, watches,
respawns and stops.
"""
from __future__ import annotations

import os
import shlex
import shutil
from pathlib import Path
from typing import Any

from zros.launch.action import Action, ActionKwargs
from zros.launch.descriptions.executable import Executable, full_environment
from zros.launch.errors import LaunchFileError, Origin
from zros.launch.plan import OUTPUT_MODES, ProcessSpec
from zros.launch.template import Text, Typed, is_static

__all__ = ['ExecuteLocal', 'ExecuteLocalKwargs', 'DEFAULT_SIGTERM_TIMEOUT', 'DEFAULT_SIGKILL_TIMEOUT', 'check_program',
           'process_label']

DEFAULT_SIGTERM_TIMEOUT = 5.0
DEFAULT_SIGKILL_TIMEOUT = 5.0

_OUTPUT_SOURCES = ('stdout', 'stderr', 'both')
_OUTPUT_DESTINATIONS = ('screen', 'log', 'own_log')


class ExecuteLocalKwargs(ActionKwargs, total=False):
    output: Text | None
    respawn: Typed | None
    respawn_delay: Typed | None
    respawn_max_retries: Typed | None
    sigterm_timeout: Typed | None
    sigkill_timeout: Typed | None
    shell: Typed | None
    emulate_tty: Typed | None
    on_exit: Any


def check_program(program: str, options: dict, context: Any, origin: Origin) -> None:
    """The program must exist (on PATH, or as a path), so a typo stops the launch up front."""
    env = dict(context.environment)
    env.update({k: v for k, v in options['env'] if v is not None})
    if os.sep in program:
        path = Path(options['cwd'] or '.') / program if not os.path.isabs(program) else Path(program)
        ok = path.is_file() and os.access(path, os.X_OK)
    else:
        ok = shutil.which(program, path=env.get('PATH')) is not None
    if not ok:
        raise LaunchFileError(origin, f"executable '{program}' not found" + ('' if os.sep in program else ' on PATH'))


def process_label(text: str) -> str:
    """A process label usable in output prefixes and log file names."""
    clean = ''.join(c if c.isalnum() or c in '_.-' else '_' for c in text.strip())
    return clean or 'process'



def _output_mode(config: dict, origin: Any) -> str:
    """launch's `output={'stdout': ..., 'stderr': ..., 'both': ...}` as the supervisor's mode,
    which only decides what reaches the screen (log files always get the output)."""
    screen: dict[str, bool] = {}
    for source, destinations in config.items():
        wanted = {destinations} if isinstance(destinations, str) else set(destinations)
        if source not in _OUTPUT_SOURCES or not wanted <= set(_OUTPUT_DESTINATIONS):
            raise LaunchFileError(origin, f'expected {{stdout|stderr|both: screen|log|own_log}}, '
                                          f'got {source!r}: {destinations!r}')
        screen[source] = 'screen' in wanted
    if screen.get('both') or screen.get('stdout'):
        return 'screen'
    return 'log' if screen.get('stderr') else 'own_log'


class ExecuteLocal(Action):
    """`ExecuteLocal(process_description=Executable(...), shell, output, respawn, respawn_delay,
    respawn_max_retries, sigterm_timeout, sigkill_timeout, emulate_tty, on_exit, log_cmd,
    cached_output)`.

    With `shell=True` the command line is run by /bin/sh. `on_exit` takes actions (or a
    function of the exit event and context returning actions), run when the process exits, as
    `RegisterEventHandler(OnProcessExit(...))` would. After `execute`, `process_details` holds
    the resolved `cmd`, `name`, `cwd` and `env` (the whole environment), as in launch.
    """

    completes_on_exit = True

    def __init__(self, *, process_description: Executable, shell: Any = None, output: Any = None,
                 respawn: Any = None, respawn_delay: Any = None, respawn_max_retries: Any = None,
                 sigterm_timeout: Any = None, sigkill_timeout: Any = None, emulate_tty: Any = None,
                 on_exit: Any = None, log_cmd: Any = None, cached_output: Any = None, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        if not isinstance(process_description, Executable):
            raise LaunchFileError(self.origin.with_key('process_description'),
                                  f'expected a launch.descriptions.Executable, got {type(process_description).__name__}')
        self.process_description = process_description
        self._shell = self._typed(shell, bool, 'shell')
        self.output = self._output(output)
        self.respawn = self._typed(respawn, bool, 'respawn')
        self.respawn_delay = self._non_negative(self._typed(respawn_delay, float, 'respawn_delay'))
        self.respawn_max_retries = self._typed(respawn_max_retries, int, 'respawn_max_retries')
        self.sigterm_timeout = self._non_negative(self._typed(sigterm_timeout, float, 'sigterm_timeout'))
        self.sigkill_timeout = self._non_negative(self._typed(sigkill_timeout, float, 'sigkill_timeout'))
        self._emulate_tty = self._typed(emulate_tty, bool, 'emulate_tty')
        self.log_cmd = self._typed(log_cmd, bool, 'log_cmd')
        self.cached_output = self._typed(cached_output, bool, 'cached_output')
        self._on_exit_entities = [on_exit] if isinstance(on_exit, Action) else on_exit
        self.on_exit_shutdown, self.on_exit = self._on_exit(self._on_exit_entities)
        self.process_details: dict[str, Any] | None = None

    def _output(self, output: Any) -> Text | None:
        if isinstance(output, dict):
            output = _output_mode(output, self.origin.with_key('output'))
        text = self._optional_text(output, 'output')
        if text is not None and is_static(text.template) and ''.join(text.template) not in OUTPUT_MODES:
            raise LaunchFileError(text.origin, f"expected one of {', '.join(OUTPUT_MODES)}, "
                                               f"got '{''.join(text.template)}'")
        return text

    @staticmethod
    def _on_exit(actions: Any) -> tuple[bool, Any]:
        """`on_exit`: a lone Shutdown is the supervisor's own `on_exit: shutdown`; anything
        else becomes an OnProcessExit handler for this process."""
        from zros.launch.actions.shutdown import Shutdown
        if actions is None:
            return False, None
        if isinstance(actions, list) and len(actions) == 1 and type(actions[0]) is Shutdown \
                and actions[0].condition is None and actions[0].reason is None:
            return True, None
        return False, actions

    @staticmethod
    def _non_negative(value: Typed | None) -> Typed | None:
        if value is not None and not isinstance(value.value, Text) and value.value < 0:
            raise LaunchFileError(value.origin, f'expected a non-negative number, got {value.value:g}')
        return value

    # -- launch's view of the description --------------------------------------------------------
    @property
    def shell(self) -> Any:
        return False if self._shell is None else self._shell.launch_view()

    @property
    def emulate_tty(self) -> Any:
        return False if self._emulate_tty is None else self._emulate_tty.launch_view()

    @property
    def cmd(self) -> list[Text]:
        return self.process_description.cmd

    @property
    def name(self) -> Text | None:
        return self.process_description.name

    @property
    def cwd(self) -> Text | None:
        return self.process_description.cwd

    @property
    def env(self) -> list[tuple[Text, Text]] | None:
        return self.process_description.env

    @property
    def additional_env(self) -> list[tuple[Text, Text]]:
        return self.process_description.additional_env

    def get_sub_entities(self) -> list[Action]:
        """The `on_exit` actions (none for an `on_exit` function)."""
        return list(self._on_exit_entities) if isinstance(self._on_exit_entities, list) else []

    # -- resolution --------------------------------------------------------------------------
    def _number(self, value: Typed | None, default: Any, context: Any) -> Any:
        if value is None:
            return default
        result = value.perform(context)
        if isinstance(result, float) and result < 0:
            raise LaunchFileError(value.origin, f'expected a non-negative number, got {result:g}')
        return result

    def _timeout_default(self, name: str, fallback: float, context: Any) -> float:
        """launch's rule: the `sigterm_timeout` / `sigkill_timeout` launch configurations are
        the defaults, so `zros launch f.yaml sigterm_timeout:=10` changes every process."""
        text = context.configurations.get(name)
        if text is None:
            return fallback
        try:
            return float(text)
        except ValueError:
            raise LaunchFileError(self.origin, f"launch configuration '{name}' must be a number, got '{text}'") from None

    def _terminal_wanted(self, context: Any) -> bool:
        """`emulate_tty`, else the `emulate_tty` launch configuration (launch's default rule)."""
        if self._emulate_tty is not None:
            return self._emulate_tty.perform(context)
        text = context.configurations.get('emulate_tty')
        return False if text is None else Typed.of(text, bool, self.origin.with_key('emulate_tty')).perform(context)

    def process_options(self, context: Any) -> dict[str, Any]:
        """ProcessSpec fields every process action shares, resolved."""
        output = os.environ.get('OVERRIDE_LAUNCH_PROCESS_OUTPUT') or (
            self.output.perform(context) if self.output is not None else 'log')
        if output not in OUTPUT_MODES:
            origin = self.output.origin if self.output is not None else self.origin
            raise LaunchFileError(origin, f"expected one of {', '.join(OUTPUT_MODES)}, got '{output}'")
        description = self.process_description
        cwd = description.cwd.perform(context) if description.cwd is not None else None
        if cwd is not None and not os.path.isdir(cwd):
            raise LaunchFileError(description.cwd.origin, f"no such directory '{cwd}'")
        for accepted in (self.log_cmd, self.cached_output):
            if accepted is not None:   # accepted for compatibility; output is always line-buffered
                accepted.perform(context)
        return dict(
            env=tuple(description.environment_changes(context).items()),
            cwd=cwd,
            output=output,
            respawn=self.respawn.perform(context) if self.respawn is not None else False,
            respawn_delay=self._number(self.respawn_delay, 0.0, context),
            respawn_max_retries=self._number(self.respawn_max_retries, -1, context),
            sigterm_timeout=self._number(self.sigterm_timeout,
                                         self._timeout_default('sigterm_timeout', DEFAULT_SIGTERM_TIMEOUT, context),
                                         context),
            sigkill_timeout=self._number(self.sigkill_timeout,
                                         self._timeout_default('sigkill_timeout', DEFAULT_SIGKILL_TIMEOUT, context),
                                         context),
            on_exit_shutdown=self.on_exit_shutdown,
            emulate_tty=self._terminal_wanted(context),
            origin=self.origin,
            source=self,
        )

    def after_start(self) -> list[Action]:
        """The OnProcessExit handler that `on_exit` asks for, if any."""
        if self.on_exit is None:
            return []
        from zros.launch.actions.events import RegisterEventHandler
        from zros.launch.event_handlers import OnProcessExit
        handler = OnProcessExit(target_action=self, on_exit=self.on_exit, origin=self.origin.with_key('on_exit'))
        return [RegisterEventHandler(handler, origin=self.origin)]

    def emit_process(self, context: Any, spec: ProcessSpec) -> list[Action]:
        """Hand `spec` to the launch and record what launch's `process_details` shows."""
        self.process_details = {'type': 'process', 'cmd': list(spec.cmd_head), 'name': spec.label,
                                'cwd': spec.cwd, 'env': full_environment(context, spec.env)}
        context.emit(spec)
        return self.after_start()

    def execute(self, context: Any) -> list[Action]:
        shell = self._shell.perform(context) if self._shell is not None else False
        options = self.process_options(context)
        description = self.process_description
        description.prepare(context, self, shell=shell)
        shell_text = None
        if shell:   # final_cmd is [*prefix, '/bin/sh', '-c', line]
            prefix, line = description.final_cmd[:-3], description.final_cmd[-1]
            shell_text = shlex.join(prefix) + ' ' + line if prefix else line
        else:
            check_program(description.final_program, options, context, description.command.origin)
        spec = ProcessSpec(label=process_label(description.final_name), cmd_head=tuple(description.final_cmd),
                           shell_text=shell_text, **options)
        return self.emit_process(context, spec)
