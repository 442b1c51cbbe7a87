"""The supervisor: carries out a resolved Plan and keeps its processes in line.

One thread (the main thread) does everything: it starts processes, reads their output through
a selector, fires timers and respawns, and handles signals, which arrive as bytes on a wakeup
pipe. That thread starting every child matters: `PR_SET_PDEATHSIG` fires when the *thread*
that forked the child dies, so children spawned from the main thread die exactly when the
supervisor does, even by SIGKILL. Children also get their own session (process group), so a
Ctrl-C in the terminal reaches only the supervisor, which then shuts them down in order:
SIGINT to each process group, SIGTERM after `sigterm_timeout`, SIGKILL `sigkill_timeout` later.

While the launch runs the supervisor holds a zros Context, so the first launch of a domain is
the loopback discovery hub for all its nodes (docs/architecture.md §5) and the hub lives as long as the
launch; the context is closed only after every child is gone.
"""
from __future__ import annotations

import contextlib
import ctypes
import datetime
import errno
import heapq
import itertools
import os
import selectors
import shlex
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path
from typing import Any, Callable, Iterator, TextIO

from zros.launch.errors import LaunchError
from zros.launch.plan import (CallEffect, ChangeStateEffect, EventHandlerEffect, GeneratedParams, LogMessage, Plan,
                              ProcessSpec, ShutdownEffect, TaskEffect, TimerEffect)

__all__ = ['Supervisor', 'ProcessObserver', 'LaunchLog', 'make_log_dir', 'default_log_base']

_PR_SET_PDEATHSIG = 1
_READ_CHUNK = 65536
_POLL_INTERVAL_S = 0.25   # re-check children even if a SIGCHLD wakeup got lost


def default_log_base() -> Path:
    """`ZROS_LOG_DIR`, else `~/.zros/log` (each run gets a timestamped directory inside)."""
    configured = os.environ.get('ZROS_LOG_DIR')
    return Path(configured).expanduser() if configured else Path.home() / '.zros' / 'log'


def make_log_dir(log_dir: str | None) -> Path:
    """The run's log directory path (not created): `log_dir` as given, or
    `<base>/<YYYY-MM-DD-HH-MM-SS-micro>` under `default_log_base()`."""
    if log_dir:
        return Path(log_dir).expanduser().resolve()
    stamp = datetime.datetime.now().strftime('%Y-%m-%d-%H-%M-%S-%f')
    return default_log_base() / stamp


def _make_preexec() -> Callable[[], None]:
    """A preexec_fn that gives the child default SIGINT/SIGTERM/SIGHUP dispositions (a launch
    started in the background or under nohup inherits them *ignored*, and `exec` keeps an
    ignored signal ignored), ties the child's life to this thread (Linux) and checks the parent
    did not die before that took effect. Everything it needs is looked up here, before fork."""
    reset = [(int(s), signal.SIG_DFL) for s in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)]
    set_disposition = signal.signal
    prctl = None
    if sys.platform.startswith('linux'):
        try:
            prctl = ctypes.CDLL(None, use_errno=True).prctl
        except (OSError, AttributeError):
            prctl = None
    parent = os.getpid()
    sigkill = int(signal.SIGKILL)
    getppid, exit_now = os.getppid, os._exit

    def preexec() -> None:
        for signum, disposition in reset:
            set_disposition(signum, disposition)
        if prctl is not None:
            prctl(_PR_SET_PDEATHSIG, sigkill, 0, 0, 0)
            if getppid() != parent:
                exit_now(1)
    return preexec


class LaunchLog:
    """Supervisor messages and child output, to the screen and to `launch.log`.

    Screen format is ros2 launch's: `[INFO] [talker-1]: process started with pid [N]` and
    `[talker-1] <line>`; launch.log lines carry a wall-clock timestamp in front.

    Child output is collected and written by `flush()`, once per pass of the supervisor's loop:
    a hundred nodes print thousands of lines a second, and a write and flush per line kept the
    supervisor seconds behind. A supervisor message flushes what came before it, in order.
    """

    def __init__(self, log_dir: Path | None, *, debug: bool = False, screen: TextIO | None = None) -> None:
        self.debug_enabled = debug
        self._screen = screen or sys.stdout
        self._file = open(log_dir / 'launch.log', 'a', encoding='utf-8') if log_dir is not None else None
        self._lock = threading.Lock()
        self._screen_pending: list[str] = []
        self._file_pending: list[str] = []

    def message(self, level: str, name: str, text: str) -> None:
        line = f'[{level}] [{name}]: {text}\n'
        with self._lock:
            if level != 'DEBUG' or self.debug_enabled:
                self._screen_pending.append(line)
            if self._file is not None:
                self._file_pending.append(f'{time.time():.7f} {line}')
        self.flush()

    def info(self, name: str, text: str) -> None:
        self.message('INFO', name, text)

    def warning(self, name: str, text: str) -> None:
        self.message('WARNING', name, text)

    def error(self, name: str, text: str) -> None:
        self.message('ERROR', name, text)

    def debug(self, name: str, text: str) -> None:
        self.message('DEBUG', name, text)

    def output(self, name: str, lines: list[str], *, to_screen: bool, to_file: bool) -> None:
        """Lines a process printed (written at the next `flush()`)."""
        with self._lock:
            if to_screen:
                self._screen_pending.extend(f'[{name}] {line}\n' for line in lines)
            if to_file and self._file is not None:
                stamp = f'{time.time():.7f}'
                self._file_pending.extend(f'{stamp} [{name}] {line}\n' for line in lines)

    def flush(self) -> None:
        with self._lock:
            screen, self._screen_pending = ''.join(self._screen_pending), []
            text, self._file_pending = ''.join(self._file_pending), []
            if screen:
                try:
                    self._screen.write(screen)
                    self._screen.flush()
                except (BrokenPipeError, ValueError, OSError):
                    pass
            if text and self._file is not None:
                self._file.write(text)
                self._file.flush()

    def close(self) -> None:
        self.flush()
        with self._lock:
            if self._file is not None:
                self._file.close()
                self._file = None


class ProcessObserver:
    """What a launch's processes do, told as it happens (launch_testing's proc_info and
    proc_output). The supervisor's thread calls these; they must return at once. `name` is the
    process's name in the output (`talker-1`), `spec.source` the action that made it."""

    def started(self, name: str, spec: ProcessSpec, pid: int, cmd: list[str]) -> None:
        """The process was started."""

    def output(self, name: str, spec: ProcessSpec, is_stderr: bool, lines: list[str]) -> None:
        """Whole lines it printed on stdout or stderr."""

    def exited(self, name: str, spec: ProcessSpec, pid: int, returncode: int, cmd: list[str]) -> None:
        """It exited with `returncode` (negative: killed by that signal)."""

    def shutting_down(self, reason: str) -> None:
        """The launch starts shutting down (Ctrl-C, a Shutdown effect, a process's on_exit)."""

    def pump(self) -> None:
        """Each pass of the loop: carry out what other threads asked for since (a
        LaunchService's queued events); `Supervisor.wake()` makes a pass happen now."""

    def idle(self) -> bool:
        """The launch has nothing left to do; True if the observer gave it more (a
        LaunchService's pending events, or its shutdown when idle), False to let it end."""
        return False


class _Process:
    """One process of the plan, across its respawns (same name, same log file)."""

    def __init__(self, spec: ProcessSpec, name: str, log_dir: Path | None) -> None:
        self.spec = spec
        self.name = name
        self.popen: subprocess.Popen | None = None
        self.starts = 0
        self.stage = 0            # 0 running normally, 1 SIGINT sent, 2 SIGTERM sent, 3 SIGKILL sent
        self.buffers: dict[int, bytearray] = {}
        self.streams: tuple[Any, ...] = ()   # what its stdout and stderr are read from
        self.command: list[str] = []
        self.log = open(log_dir / f'{name}.log', 'a', encoding='utf-8') if log_dir is not None else None

    @property
    def running(self) -> bool:
        return self.popen is not None and self.popen.returncode is None

    def close(self) -> None:
        if self.log is not None:
            self.log.close()
            self.log = None


class _Transition:
    """A lifecycle transition requested of one process's node, under way as a child command."""

    def __init__(self, process: _Process, effect: ChangeStateEffect, popen: subprocess.Popen) -> None:
        self.process = process
        self.start = process.starts      # the node's process as it was when asked
        self.effect = effect
        self.popen = popen

    def output(self) -> str:
        """What the command printed (it has exited; a one-line answer fits in the pipe)."""
        try:
            return self.popen.stdout.read().decode('utf-8', errors='replace').strip()
        finally:
            self.popen.stdout.close()


class _Task:
    """A TaskEffect under way on its own thread; the supervisor collects what it returned."""

    def __init__(self, effect: TaskEffect, wake: Callable[[], None]) -> None:
        self.effect = effect
        self.stop = threading.Event()
        self.effects: list = []
        self.error: Exception | None = None
        self._wake = wake
        self.thread = threading.Thread(target=self._run, name=effect.label, daemon=True)

    def _run(self) -> None:
        try:
            self.effects = list(self.effect.function(self.stop) or [])
        except Exception as exc:  # noqa: BLE001 - reported by the supervisor's thread, which fails the launch
            self.error = exc
        finally:
            self._wake()


class Supervisor:
    """Runs a Plan to the end.

    Construct it and call `run()` from the main thread (it installs signal handlers and must
    be the thread that forks the children), or await `run_async()` on an asyncio loop that the
    main thread runs. `run()` returns when every process has exited and
    no timer or respawn is pending, or after a shutdown; the exit status is 0, or 1 when a
    process could not be started at all.

    Args:
        plan: the resolved launch.
        log_dir: where launch.log, per-process logs and generated parameter files go (created);
            None keeps no files (output still reaches the screen).
        debug: also print DEBUG messages (command lines, environment, signals).
        hub: open a zros Context for the launch's duration (local discovery for the nodes).
        observer: told of every process start, output line and exit.
        keep_alive: run until a shutdown, even when no process is left (launch_testing's
            `keep_alive` marker); otherwise the launch ends when it has nothing left to do.
    """

    def __init__(self, plan: Plan, *, log_dir: Path | None, debug: bool = False, hub: bool = True,
                 screen: TextIO | None = None, observer: ProcessObserver | None = None,
                 keep_alive: bool = False) -> None:
        self.plan = plan
        self.log_dir = log_dir
        self._temporary_params_dir: Path | None = None
        self.debug = debug
        self.hub = hub
        self._screen = screen
        self._observer = observer or ProcessObserver()
        self._keep_alive = keep_alive
        self._requests: list[str] = []      # shutdowns asked for by other threads
        self.log: LaunchLog | None = None
        self._processes: list[_Process] = []
        self._counter = itertools.count(1)
        self._timers: list[tuple[float, int, str, Callable[[], None]]] = []   # (due, seq, kind, callback)
        self._sim_waits: list[tuple[Any, list]] = []   # ROSTimers on sim time: (SimTimeWait, effects)
        self._timer_seq = itertools.count()
        self._selector: selectors.BaseSelector | None = None
        self._signals: list[int] = []
        self._shutting_down = False
        self._failed = False
        self._preexec = None
        self._wakeup_read = self._wakeup_write = -1
        self._wakeup_lock = threading.Lock()    # request_shutdown() never writes to a closed fd
        self._context = None
        self._handlers: list[EventHandlerEffect] = []
        self._transitions: list[_Transition] = []
        self._tasks: list[_Task] = []
        self._child_exited = False      # SIGCHLD came in since the last `_reap()`
        self._reaped_at = 0.0
        self._unflushed: set[_Process] = set()   # per-process logs written since the last flush

    # -- life cycle ----------------------------------------------------------------------------
    def run(self) -> int:
        """Run the plan to the end on this (the main) thread; the exit status."""
        with self._running():
            while self._pass():
                self._serve(self._selector.select(self._wait_s()))
        return 1 if self._failed else 0

    async def run_async(self) -> int:
        """`run()` as a coroutine of the running asyncio loop, which must be the main thread's:
        the same passes, but each wait for output, signals or timers is awaited, so the loop's
        other tasks (a caller's `asyncio.sleep`, then its shutdown) run meanwhile. The children
        are forked from this thread as under `run()`, so they still die with it."""
        import asyncio
        loop = asyncio.get_running_loop()
        with self._running():
            while self._pass():
                await _readable(loop, self._selector, self._wait_s())
                self._serve(self._selector.select(0))
        return 1 if self._failed else 0

    @contextlib.contextmanager
    def _running(self) -> Iterator[None]:
        """Set up (log, selector, signals, hub, the plan's first effects) and, however the run
        ends, stop every child and put the signals back."""
        if threading.current_thread() is not threading.main_thread():
            raise RuntimeError('Supervisor.run() must be called from the main thread')
        if self.log_dir is not None:
            self.log_dir.mkdir(parents=True, exist_ok=True)
            _update_latest_link(self.log_dir)
        self.log = LaunchLog(self.log_dir, debug=self.debug, screen=self._screen)
        self._preexec = _make_preexec()
        self._selector = selectors.DefaultSelector()
        previous = self._install_signals()
        try:
            if self.log_dir is not None:
                self.log.info('launch', f'All log files can be found below {self.log_dir}')
            self.log.info('launch', 'Default logging verbosity is set to ' + ('DEBUG' if self.debug else 'INFO'))
            if self.hub:
                self._open_hub()
            self._run_effects(self.plan.effects)
            yield
        finally:
            self._cancel_sim_waits()
            self._stop_tasks(wait=2.0)
            self._kill_all()
            if self._temporary_params_dir is not None:
                shutil.rmtree(self._temporary_params_dir, ignore_errors=True)
            self._restore_signals(previous)
            self._close_hub()
            for process in self._processes:
                process.close()
            self._selector.close()
            self.log.close()

    def _open_hub(self) -> None:
        from zros.context import Context
        self._context = Context().init([], install_signal_handlers=False)
        role = 'is the discovery hub' if self._context.is_hub else 'joined the running discovery hub'
        self.log.debug('launch', f'zros domain {self._context.domain_id}: this launch {role}')

    @property
    def context(self) -> Any:
        """The zros Context the launch holds while it runs (None before and after)."""
        return self._context

    def request_shutdown(self, reason: str) -> None:
        """Ask for `shutdown(reason)` from any thread (a launch test's, when its tests are done)."""
        self._requests.append(reason)
        self.wake()

    def wake(self) -> None:
        """Make the loop pass now (from any thread): the observer's `pump()` runs."""
        with self._wakeup_lock:
            if self._wakeup_write >= 0:
                try:
                    os.write(self._wakeup_write, b'\0')
                except OSError:
                    pass   # the pipe is full: a wakeup is pending anyway

    def _close_hub(self) -> None:
        if self._context is not None:
            self._context.shutdown()
            self._context = None

    # -- signals -------------------------------------------------------------------------------
    def _install_signals(self) -> dict:
        self._wakeup_read, self._wakeup_write = os.pipe()
        os.set_blocking(self._wakeup_read, False)
        os.set_blocking(self._wakeup_write, False)
        self._selector.register(self._wakeup_read, selectors.EVENT_READ, None)
        previous = {'wakeup': signal.set_wakeup_fd(self._wakeup_write, warn_on_full_buffer=False)}

        def on_signal(signum: int, frame: Any) -> None:
            self._signals.append(signum)

        def on_child(signum: int, frame: Any) -> None:
            self._child_exited = True

        for signum in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP, signal.SIGCHLD):
            previous[signum] = signal.signal(signum, on_signal if signum != signal.SIGCHLD else on_child)
        return previous

    def _restore_signals(self, previous: dict) -> None:
        for signum, handler in previous.items():
            if signum != 'wakeup':
                signal.signal(signum, handler if handler is not None else signal.SIG_DFL)
        signal.set_wakeup_fd(previous['wakeup'])
        with self._wakeup_lock:
            for fd in (self._wakeup_read, self._wakeup_write):
                try:
                    os.close(fd)
                except OSError:
                    pass
            self._wakeup_read = self._wakeup_write = -1

    def _handle_signals(self) -> None:
        while self._requests:
            self.shutdown(self._requests.pop(0))
        while self._signals:
            signum = self._signals.pop(0)
            if signum == signal.SIGINT:
                what = 'user interrupted with ctrl-c (SIGINT)'
            else:
                what = f'received {signal.Signals(signum).name}'
            if not self._shutting_down:
                self.log.warning('launch', what)
                self.shutdown(what)
            else:
                self.log.warning('launch', f'{what} again, escalating')
                self._escalate_all()

    # -- effects -------------------------------------------------------------------------------
    def carry_out(self, effects: list) -> None:
        """Start, log, schedule ... `effects` now, from the supervisor's thread (a
        LaunchService's handlers resolve actions while the launch runs)."""
        self._run_effects(effects)

    def _run_effects(self, effects: list) -> None:
        # Handlers first: an OnProcessStart written after its node still sees the node start.
        self._handlers += [effect for effect in effects if isinstance(effect, EventHandlerEffect)]
        for effect in effects:
            if self._shutting_down:
                return
            if isinstance(effect, ProcessSpec):
                process = _Process(effect, f'{effect.label}-{next(self._counter)}', self.log_dir)
                self._processes.append(process)
                self._start(process)
            elif isinstance(effect, LogMessage):
                self.log.message(effect.level, effect.logger, effect.message)
            elif isinstance(effect, TimerEffect):
                if effect.sim_time is not None and effect.sim_time():
                    from zros.launch.ros_time import SimTimeWait
                    self._sim_waits.append((SimTimeWait(effect.period, self.wake), effect.effects))
                elif effect.cancel_on_shutdown:
                    self._schedule(effect.period, 'timer', lambda e=effect: self._run_effects(e.effects))
                else:
                    self._schedule(effect.period, 'kept-timer', lambda e=effect: self._run_kept(e.effects))
            elif isinstance(effect, ShutdownEffect):
                self.shutdown(effect.reason or 'shutdown requested by the launch file',
                              sigint_delivered=effect.sigint_delivered)
                return
            elif isinstance(effect, CallEffect):
                effect.function()
            elif isinstance(effect, TaskEffect):
                task = _Task(effect, self.wake)
                self._tasks.append(task)
                self.log.debug('launch', effect.label)
                task.thread.start()
            elif isinstance(effect, ChangeStateEffect):
                self._change_state(effect)

    def _run_kept(self, effects: list) -> None:
        """A timer that shutdown does not cancel: as usual before the shutdown; during it, its
        log lines are logged and its shutdowns announced again (nothing starts any more)."""
        if not self._shutting_down:
            self._run_effects(effects)
            return
        for effect in effects:
            if isinstance(effect, LogMessage):
                self.log.message(effect.level, effect.logger, effect.message)
            elif isinstance(effect, ShutdownEffect):
                self._announce_shutdown(effect.reason or 'shutdown requested by the launch file')

    def _dispatch(self, event: str, process: _Process, code: int | None = None) -> None:
        """Carry out the OnProcessStart / OnProcessExit handlers that watch this process."""
        for handler in [h for h in self._handlers if h.event == event and h.matches(process.spec)]:
            self._run_effects(handler.effects_for(process.name, process.popen.pid, code, process.command))

    # -- lifecycle transitions -------------------------------------------------------------------
    def _change_state(self, effect: ChangeStateEffect) -> None:
        """Start `zros lifecycle set` for each running lifecycle node the event is aimed at."""
        targets = []
        for process in self._processes:
            try:
                if process.running and effect.matches(process.spec):
                    targets.append(process)
            except Exception as exc:  # noqa: BLE001 - a user's matcher function failing is reported, not fatal
                self.log.error('launch', f'ChangeState {effect.label}: lifecycle_node_matcher failed: '
                                         f'{type(exc).__name__}: {exc}')
                return
        if not targets:
            self.log.warning('launch', f"ChangeState '{effect.label}': no running lifecycle node of this launch "
                                       'matches; nothing to do')
        for process in targets:
            self._start_transition(process, effect)

    def _start_transition(self, process: _Process, effect: ChangeStateEffect) -> None:
        from zros.launch.lifecycle import TRANSITION_WAIT_S
        node = process.spec.node.display_name()
        cmd = [sys.executable, '-m', 'zros', 'lifecycle', 'set', node, str(effect.transition_id),
               '--wait', f'{TRANSITION_WAIT_S:g}']
        self.log.debug(process.name, f"lifecycle transition '{effect.label}': {shlex.join(cmd)}")
        try:
            popen = subprocess.Popen(cmd, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                     env=self._environment(process.spec), start_new_session=True,
                                     preexec_fn=self._preexec)
        except OSError as exc:
            self.log.error(process.name, f"cannot request lifecycle transition '{effect.label}' of {node}: {exc}")
            return
        self._transitions.append(_Transition(process, effect, popen))

    def _reap_transitions(self) -> None:
        for transition in [t for t in self._transitions if t.popen.poll() is not None]:
            self._transitions.remove(transition)
            output = transition.output()
            process, effect = transition.process, transition.effect
            if not process.running or process.starts != transition.start:
                continue   # the node's process is gone (or respawned): the answer is about the old one
            node = process.spec.node.display_name()
            if transition.popen.returncode != 0:
                reason = output.splitlines()[-1] if output else f'exit code {transition.popen.returncode}'
                self.log.error(process.name, f"failed to make lifecycle transition '{effect.label}' of {node}: {reason}")
                continue
            self._transition_done(process, effect)

    def _transition_done(self, process: _Process, effect: ChangeStateEffect) -> None:
        """Report both steps of a successful transition to the OnStateTransition handlers."""
        from zros.launch.lifecycle import StateTransition
        from zros.lifecycle.state_machine import successful_steps
        steps = successful_steps(effect.transition_id)
        self.log.info(process.name, f"lifecycle transition '{effect.label}' of {process.spec.node.display_name()} "
                                    f'done: now {steps[-1].goal.label}')
        for step in steps:
            event = StateTransition(process.spec.source, step.label, step.start.label, step.goal.label, process.name)
            for handler in [h for h in self._handlers if h.event == 'transition' and h.matches(process.spec)]:
                try:
                    fires = handler.transition.matches(event)
                except Exception as exc:  # noqa: BLE001 - a user's matcher function failing is reported, not fatal
                    self.log.error('launch', f'OnStateTransition matcher failed: {type(exc).__name__}: {exc}')
                    continue
                if fires:
                    self._run_effects(handler.effects)

    def _abandon_transitions(self, process: _Process | None = None) -> None:
        """Stop the transition commands for `process` (None: all): it exited, or the launch ends."""
        from zros.process_group import kill_group
        for transition in [t for t in self._transitions if process is None or t.process is process]:
            self._transitions.remove(transition)
            kill_group(transition.popen)
            transition.popen.stdout.close()

    def _collect_tasks(self) -> None:
        """Carry out what finished tasks returned (only their log lines once shutting down)."""
        for task in [t for t in self._tasks if not t.thread.is_alive()]:
            self._tasks.remove(task)
            if isinstance(task.error, LaunchError):
                self.fail('launch', str(task.error))
            elif task.error is not None:
                self.fail('launch', f'{task.effect.label}: {type(task.error).__name__}: {task.error}')
            else:
                self._run_kept(task.effects)

    def _stop_tasks(self, wait: float = 0.0) -> None:
        for task in self._tasks:
            task.stop.set()
        for task in self._tasks:
            task.thread.join(wait)

    def _schedule(self, delay: float, kind: str, callback: Callable[[], None]) -> None:
        heapq.heappush(self._timers, (time.monotonic() + delay, next(self._timer_seq), kind, callback))

    # -- processes -----------------------------------------------------------------------------
    def _params_paths(self, process: _Process) -> list[str]:
        spec = process.spec
        directory = self._params_dir()
        paths = spec.generated_params_paths(directory, process.name)
        if process.starts == 0:
            for source, path in zip(spec.params, paths):
                if isinstance(source, GeneratedParams):
                    directory.mkdir(parents=True, exist_ok=True)
                    Path(path).write_text(source.to_yaml(), encoding='utf-8')
        return paths

    def _cancel_sim_waits(self) -> None:
        for wait, _ in self._sim_waits:
            wait.cancel()
        self._sim_waits.clear()

    def _params_dir(self) -> Path:
        """Where generated parameter files go: `<log dir>/params`, or without a log directory
        (a LaunchService run from code) a temporary directory kept while the run lasts (a
        respawned node reads its file again) and removed when it ends."""
        if self.log_dir is not None:
            return self.log_dir / 'params'
        if self._temporary_params_dir is None:
            self._temporary_params_dir = Path(tempfile.mkdtemp(prefix='launch_params_'))
        return self._temporary_params_dir

    def _environment(self, spec: ProcessSpec) -> dict[str, str]:
        env = dict(os.environ)
        for name, value in spec.env:
            if value is None:
                env.pop(name, None)
            else:
                env[name] = value
        env['PYTHONUNBUFFERED'] = '1'   # lines arrive as they are printed
        return env

    def _start(self, process: _Process) -> None:
        spec = process.spec
        process.command = spec.command(self._params_paths(process))
        shown = spec.shell_text if spec.shell_text is not None else shlex.join(process.command)
        self.log.debug(process.name, f'cmd: {shown}')
        if spec.env:
            self.log.debug(process.name, 'env: ' + ', '.join(
                f'{k}={v}' if v is not None else f'unset {k}' for k, v in spec.env))
        terminals = _open_terminals() if spec.emulate_tty else None
        outputs = terminals[1] if terminals else (subprocess.PIPE, subprocess.PIPE)
        try:
            popen = subprocess.Popen(
                process.command, stdin=subprocess.DEVNULL, stdout=outputs[0], stderr=outputs[1],
                env=self._environment(spec), cwd=spec.cwd, start_new_session=True, preexec_fn=self._preexec)
        except OSError as exc:
            for fd in [fd for pair in terminals or () for fd in pair]:
                os.close(fd)
            self.log.error(process.name, f'failed to start process: {exc.strerror or exc} (cmd {shown!r})')
            self._failed = True
            if spec.on_exit_shutdown:
                self.shutdown(f'process[{process.name}] failed to start')
            return
        if terminals:   # the child has its ends; the launch reads the other ones
            for fd in terminals[1]:
                os.close(fd)
            process.streams = tuple(os.fdopen(fd, 'rb', buffering=0) for fd in terminals[0])
        else:
            process.streams = (popen.stdout, popen.stderr)
        process.popen = popen
        process.starts += 1
        process.stage = 0
        for stream in process.streams:
            fd = stream.fileno()
            os.set_blocking(fd, False)
            process.buffers[fd] = bytearray()
            self._selector.register(fd, selectors.EVENT_READ, (process, stream))
        self.log.info(process.name, f'process started with pid [{popen.pid}]')
        self._observer.started(process.name, spec, popen.pid, process.command)
        if self._shutting_down:   # a shutdown came in while this one was being started
            self._signal(process, signal.SIGINT)
        else:
            self._dispatch('start', process)

    def _read(self, process: _Process, stream: Any) -> None:
        fd = stream.fileno()
        while True:
            try:
                data = os.read(fd, _READ_CHUNK)
            except BlockingIOError:
                return
            except OSError as exc:
                if exc.errno == errno.EINTR:
                    continue
                data = b''
            if not data:
                self._close_stream(process, stream)
                return
            buffer = process.buffers[fd]
            buffer.extend(data)
            if b'\n' in data:
                *lines, rest = bytes(buffer).split(b'\n')
                buffer[:] = rest
                self._emit(process, stream is process.streams[1], lines)

    def _close_stream(self, process: _Process, stream: Any) -> None:
        fd = stream.fileno()
        rest = process.buffers.pop(fd, b'')
        if rest:
            self._emit(process, stream is process.streams[1], [bytes(rest)])
        try:
            self._selector.unregister(fd)
        except (KeyError, ValueError):
            pass
        stream.close()

    def _emit(self, process: _Process, is_stderr: bool, raw: list[bytes]) -> None:
        """Lines read from one of the process's pipes in one go (one write each way)."""
        lines = [line.decode('utf-8', errors='replace').rstrip('\r') for line in raw]
        output = process.spec.output
        to_screen = output in ('screen', 'both') or (is_stderr and output == 'log')
        self.log.output(process.name, lines, to_screen=to_screen, to_file=output != 'own_log')
        self._observer.output(process.name, process.spec, is_stderr, lines)
        if process.log is not None:
            process.log.write('\n'.join(lines) + '\n')
            self._unflushed.add(process)

    def _reap(self) -> None:
        """Collect the processes that exited. Run when SIGCHLD came in (and every
        `_POLL_INTERVAL_S` in case one was missed), not on every pass: polling 100 children
        for each burst of output lines was most of the supervisor's work."""
        self._child_exited = False
        self._reaped_at = time.monotonic()
        for process in self._processes:
            if process.popen is None or process.popen.returncode is not None:
                continue
            code = process.popen.poll()
            if code is None:
                continue
            for stream in process.streams:
                if not stream.closed:
                    self._read(process, stream)
                    if not stream.closed:   # a grandchild still holds the pipe: stop reading it
                        self._close_stream(process, stream)
            self._flush_logs()
            self._on_exit(process, code)
        self._reap_transitions()

    def _on_exit(self, process: _Process, code: int) -> None:
        spec, pid = process.spec, process.popen.pid
        if code == 0:
            self.log.info(process.name, f'process has finished cleanly [pid {pid}]')
        else:
            cmd = spec.shell_text if spec.shell_text is not None else ' '.join(process.command)
            self.log.error(process.name, f"process has died [pid {pid}, exit code {code}, cmd '{cmd}'].")
        self._observer.exited(process.name, spec, pid, code, process.command)
        self._abandon_transitions(process)
        self._dispatch('exit', process, code)
        if spec.on_exit_shutdown:
            self.shutdown(f'process[{process.name}] exited and has on_exit: shutdown')
            return
        retries = process.starts - 1
        if spec.respawn and not self._shutting_down and (spec.respawn_max_retries < 0
                                                         or retries < spec.respawn_max_retries):
            self.log.debug(process.name, f'respawning in {spec.respawn_delay:g} s')
            self._schedule(spec.respawn_delay, 'respawn', lambda p=process: self._respawn(p))

    def _respawn(self, process: _Process) -> None:
        if not self._shutting_down:
            self._start(process)

    # -- shutdown ------------------------------------------------------------------------------
    def fail(self, name: str, text: str) -> None:
        """An error the launch cannot go on from (an entity that does not resolve): logged, then
        a shutdown, and run() returns 1."""
        self.log.error(name, text)
        self._failed = True
        self.shutdown(text)

    def shutdown(self, reason: str, *, sigint_delivered: bool = False) -> None:
        """Stop the launch: cancel timers and respawns, SIGINT every process, escalate later.

        `sigint_delivered`: the caller says a SIGINT already reached every process (launch's
        Shutdown event `due_to_sigint` in an interactive launch: a terminal's Ctrl-C went to the
        whole process group), so the processes get SIGTERM after `sigterm_timeout` unless they
        exit first, and no SIGINT from here.
        """
        if self._shutting_down:
            return
        self._shutting_down = True
        self._announce_shutdown(reason)
        self._timers = [t for t in self._timers if t[2] in ('escalate', 'kept-timer')]
        heapq.heapify(self._timers)
        self._cancel_sim_waits()
        self._abandon_transitions()
        self._stop_tasks()
        for process in self._processes:
            if not process.running:
                continue
            if sigint_delivered and process.stage < 1:
                process.stage = 1
                self._schedule_escalation(process)
            else:
                self._signal(process, signal.SIGINT)

    def _announce_shutdown(self, reason: str) -> None:
        """Tell the observer's and the launch's OnShutdown handlers (again, for each later
        shutdown request while stopping)."""
        self.log.info('launch', f'shutting down: {reason}')
        self._observer.shutting_down(reason)
        self._on_shutdown(reason)

    def _on_shutdown(self, reason: str) -> None:
        """Carry out the OnShutdown handlers: their messages are logged; nothing starts now."""
        for handler in [h for h in self._handlers if h.event == 'shutdown']:
            try:
                effects = handler.effects_at_shutdown(reason)
            except Exception as exc:  # noqa: BLE001 - a handler's failure must not stop the shutdown
                self.log.error('launch', f'OnShutdown handler failed: {type(exc).__name__}: {exc}')
                continue
            for effect in effects or []:
                if isinstance(effect, LogMessage):
                    self.log.message(effect.level, effect.logger, effect.message)
                else:
                    self.log.warning('launch', f'OnShutdown: {type(effect).__name__} not carried out '
                                               'while the launch shuts down')

    def _signal(self, process: _Process, signum: signal.Signals) -> None:
        stage = {signal.SIGINT: 1, signal.SIGTERM: 2, signal.SIGKILL: 3}[signum]
        if not process.running or process.stage >= stage:
            return
        previous = process.stage
        process.stage = stage
        if previous:
            timeout = process.spec.sigterm_timeout if previous == 1 else process.spec.sigkill_timeout
            before = {1: 'SIGINT', 2: 'SIGTERM'}[previous]
            self.log.error(process.name, f"process[{process.name}] failed to terminate '{timeout:g}' seconds "
                                         f"after receiving '{before}', escalating to '{signum.name}'")
        self.log.info(process.name, f"sending signal '{signum.name}' to process[{process.name}]")
        try:
            os.killpg(process.popen.pid, signum)
        except (ProcessLookupError, PermissionError):
            try:
                process.popen.send_signal(signum)
            except (ProcessLookupError, OSError):
                pass
        self._schedule_escalation(process)

    def _schedule_escalation(self, process: _Process) -> None:
        """The next signal, if the process is still running after its stage's timeout."""
        if process.stage == 1:
            self._schedule(process.spec.sigterm_timeout, 'escalate',
                           lambda p=process, n=process.starts: self._escalate(p, n, signal.SIGTERM))
        elif process.stage == 2:
            self._schedule(process.spec.sigkill_timeout, 'escalate',
                           lambda p=process, n=process.starts: self._escalate(p, n, signal.SIGKILL))

    def _escalate(self, process: _Process, start: int, signum: signal.Signals) -> None:
        if process.starts == start and process.running:
            self._signal(process, signum)

    def _escalate_all(self) -> None:
        for process in self._processes:
            if process.running:
                self._signal(process, signal.SIGTERM if process.stage < 2 else signal.SIGKILL)

    def _kill_all(self) -> None:
        """Last resort when run() ends early (an exception): nothing may outlive the launch."""
        self._abandon_transitions()
        for process in self._processes:
            if process.popen is None:
                continue
            try:
                os.killpg(process.popen.pid, signal.SIGKILL)
            except (ProcessLookupError, PermissionError):
                pass
            if process.popen.returncode is None:
                try:
                    process.popen.wait(timeout=5)
                except subprocess.TimeoutExpired:  # pragma: no cover - SIGKILL does not fail
                    pass
            for stream in process.streams:
                if stream is not None and not stream.closed:
                    try:
                        self._selector.unregister(stream.fileno())
                    except (KeyError, ValueError):
                        pass
                    stream.close()

    # -- the loop ------------------------------------------------------------------------------
    def _busy(self) -> bool:
        # Escalation timers of processes that already exited keep nothing alive.
        if self._keep_alive and not self._shutting_down:
            return True
        return (any(p.running for p in self._processes) or bool(self._transitions) or bool(self._tasks)
                or any(t[2] != 'escalate' for t in self._timers) or bool(self._sim_waits))

    def _flush_logs(self) -> None:
        self.log.flush()
        for process in self._unflushed:
            if process.log is not None:
                process.log.flush()
        self._unflushed.clear()

    def _pass(self) -> bool:
        """One pass of the loop: signals, exits, due timers, the observer's work. False when
        the launch has ended (nothing left to do and the observer adds nothing)."""
        self._handle_signals()
        if self._child_exited or time.monotonic() - self._reaped_at >= _POLL_INTERVAL_S:
            self._reap()
        self._collect_tasks()
        now = time.monotonic()
        while self._timers and self._timers[0][0] <= now:
            _, _, _, callback = heapq.heappop(self._timers)
            callback()
            self._handle_signals()
        for wait, effects in [item for item in self._sim_waits if item[0].due()]:
            self._sim_waits.remove((wait, effects))
            self._run_effects(effects)
        self._observer.pump()
        return self._busy() or self._observer.idle()

    def _wait_s(self) -> float:
        """[s] the loop may wait for output or a wakeup before the next pass is due."""
        timeout = _POLL_INTERVAL_S
        if self._timers:
            timeout = max(0.0, min(timeout, self._timers[0][0] - time.monotonic()))
        return timeout

    def _serve(self, ready: list) -> None:
        """Read what the selector found ready (children's output, the wakeup pipe)."""
        for key, _ in ready:
            if key.data is None:
                _drain(self._wakeup_read)
            else:
                process, stream = key.data
                if not stream.closed:
                    self._read(process, stream)
        self._flush_logs()


async def _readable(loop: Any, selector: selectors.BaseSelector, timeout: float) -> None:
    """Wait, without blocking `loop`, until `selector` has something ready or `timeout` [s]
    passed. An epoll selector is itself a file descriptor the loop can watch; one without
    (select or poll) is polled in short sleeps instead."""
    import asyncio
    try:
        fd = selector.fileno()
    except (AttributeError, NotImplementedError):
        await asyncio.sleep(min(timeout, 0.02))
        return
    ready = loop.create_future()
    loop.add_reader(fd, lambda: ready.done() or ready.set_result(None))
    try:
        await asyncio.wait({ready}, timeout=timeout)
    finally:
        loop.remove_reader(fd)
        ready.cancel()


def _open_terminals() -> tuple[tuple[int, int], tuple[int, int]]:
    """Two pseudo-terminals for `emulate_tty`: ((stdout, stderr) ends the launch reads,
    (stdout, stderr) ends the child writes), so the child's isatty() is true and its libraries
    colour and line-buffer their output as in a terminal."""
    stdout, stdout_child = os.openpty()
    stderr, stderr_child = os.openpty()
    return (stdout, stderr), (stdout_child, stderr_child)


def _drain(fd: int) -> None:
    try:
        while os.read(fd, 4096):
            pass
    except (BlockingIOError, OSError):
        pass


def _update_latest_link(log_dir: Path) -> None:
    """`<base>/latest` -> this run, when the run lives in the default base (as ~/.ros/log/latest)."""
    base = default_log_base()
    if log_dir.parent != base:
        return
    link = base / 'latest'
    try:
        if link.is_symlink() or not link.exists():
            tmp = base / f'.latest-{os.getpid()}'
            if tmp.is_symlink():
                tmp.unlink()
            tmp.symlink_to(log_dir.name)
            os.replace(tmp, link)
    except OSError:
        pass
