"""Signal handling, as rclpy.signals: SIGINT and SIGTERM stop a zros program however it started.

A process started in the background by a shell without job control, or under nohup, inherits
SIGINT as *ignored*, and Python then never installs its KeyboardInterrupt handler: such a node
would ignore Ctrl-C and a launch's SIGINT. `zros.init()` therefore installs its own handlers for
both signals whatever the inherited disposition (rclpy does the same; opt out with
`zros.init(signal_handler_options=SignalHandlerOptions.NO)`):

- in the main thread, SIGINT raises KeyboardInterrupt (SIG_DFL and SIG_IGN inherited included).
  The program then shuts zros down itself (`with zros.init()`, `zros.shutdown()`, the exit
  hook), so its cleanup can still use its nodes: a teleop publishes its final stop command.
  (rclpy shuts the contexts down at once; zros leaves that to the program for this reason.)
- SIGTERM, and a SIGINT the program had its own handler for (which is called), shut every
  initialized context down from a watcher thread, which wakes the executors: `spin()` ends
  with ExternalShutdownException and `zros.ok()` turns False. A program without a SIGTERM
  handler of its own is ended `TERM_S` later if it is still running.

The watcher learns of a signal from the pipe Python's C-level handler writes to
(`signal.set_wakeup_fd`), so it acts even while the main thread is blocked in native code that
never returns to the interpreter, and it cannot be starved by Zenoh's threads or the executor.
It also guarantees the exit: if the main thread has not run the handler `STUCK_S` after the
signal, or the interpreter is still alive `EXIT_S` after the main thread finished, the process
exits with status 1 (faulthandler's watchdog does it, a C thread that needs no GIL). A second
SIGINT or SIGTERM while the first is being handled exits at once.

Command-line tools use `exit_on_signals(grace_s)`: both signals raise KeyboardInterrupt, and the
process is gone `grace_s` after the signal whatever it is doing.
"""
from __future__ import annotations

import enum
import faulthandler
import os
import signal
import sys
import threading
from typing import Any

__all__ = ['SignalHandlerOptions', 'install_signal_handlers', 'uninstall_signal_handlers',
           'get_current_signal_handlers_options', 'exit_on_signals', 'signal_received', 'STUCK_S', 'EXIT_S', 'TERM_S']

# How long the main thread may take to notice a signal before the process is ended for it.
STUCK_S = 2.0
# How long the interpreter may take to exit once the main thread has finished after a signal.
EXIT_S = 2.0
# How long a program that has no SIGTERM handler of its own may go on after SIGTERM.
TERM_S = 3.0


class SignalHandlerOptions(enum.IntEnum):
    """Which signals `zros.init()` handles (rclpy.signals.SignalHandlerOptions)."""
    NO = 0
    SIGINT = 1
    SIGTERM = 2
    ALL = 3


_SIGNALS = {SignalHandlerOptions.SIGINT: (signal.SIGINT,), SignalHandlerOptions.SIGTERM: (signal.SIGTERM,),
            SignalHandlerOptions.ALL: (signal.SIGINT, signal.SIGTERM), SignalHandlerOptions.NO: ()}


class _Handlers:
    """The installed handlers: what they replaced, and how a signal ends the process."""

    def __init__(self, options: SignalHandlerOptions, *, cli_grace_s: float | None) -> None:
        self.options = options
        self.cli_grace_s = cli_grace_s      # None: a program's (shut contexts down, then exit)
        self.previous: dict[int, Any] = {}

    def _own(self, signum: int) -> Any:
        """The handler the program had installed for `signum` before zros, or None."""
        previous = self.previous.get(signum)
        return previous if callable(previous) and previous is not signal.default_int_handler else None

    def stops_contexts(self, signum: int) -> bool:
        """Whether zros shuts the contexts down for `signum`: SIGTERM, and a SIGINT that does not
        become KeyboardInterrupt (the program's own handler takes it), as rclpy does."""
        return self.cli_grace_s is None and (signum == signal.SIGTERM or self._own(signum) is not None)

    def on_signal(self, signum: int, frame: Any) -> None:
        """Main thread, between two bytecodes."""
        previous = self._own(signum)
        own = previous is not None
        if self.stops_contexts(signum):
            _request_stop()
        # The program is in control once it has KeyboardInterrupt or its own handler has run.
        _watch.main_thread_saw(in_control=own or signum == signal.SIGINT or self.cli_grace_s is not None)
        if own:
            previous(signum, frame)
        elif signum == signal.SIGINT or self.cli_grace_s is not None:
            raise KeyboardInterrupt


class _Watcher:
    """The thread that acts on signals without the main thread (see the module docstring)."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._read_fd = self._write_fd = -1
        self._thread: threading.Thread | None = None
        self._handling = False
        self._main_saw: bool | None = None   # None: not yet; else whether the program is in control
        self._armed = ''                     # which exit timer is pending: '', 'stuck', 'term', 'exit'
        self._devnull: Any = None

    def start(self) -> None:
        """Route signal numbers to this watcher, unless another wakeup fd is in use (asyncio's):
        then only the handlers in the main thread act."""
        with self._lock:
            if self._thread is None:
                read_fd, write_fd = os.pipe()
                os.set_blocking(write_fd, False)
                self._read_fd, self._write_fd = read_fd, write_fd
                self._thread = threading.Thread(target=self._run, name='zros-signals', daemon=True)
                self._thread.start()
            current = signal.set_wakeup_fd(self._write_fd, warn_on_full_buffer=False)
            if current not in (-1, self._write_fd):
                signal.set_wakeup_fd(current)

    def stop(self) -> None:
        """Stop routing signals here (the thread stays, for a signal already in hand)."""
        with self._lock:
            current = signal.set_wakeup_fd(-1)
            if current not in (-1, self._write_fd):
                signal.set_wakeup_fd(current)

    def main_thread_saw(self, *, in_control: bool) -> None:
        with self._lock:
            if self._main_saw is None:
                self._main_saw = in_control
                self._settle()

    def _settle(self) -> None:
        """Pick the exit timer for the first signal (lock held)."""
        if not self._handling or self._armed in ('exit', 'cli'):
            return
        if self._main_saw is None:
            self._arm(STUCK_S, 'stuck')
        elif self._main_saw:
            if self._armed:
                faulthandler.cancel_dump_traceback_later()
                self._armed = ''
        elif self._armed != 'term':
            self._arm(TERM_S, 'term')

    def _run(self) -> None:
        while True:
            try:
                data = os.read(self._read_fd, 64)
            except InterruptedError:
                continue
            except OSError:
                return
            for signum in data:
                self._handle(signum)

    def _handle(self, signum: int) -> None:
        handlers = _installed
        if handlers is None or signum not in (signal.SIGINT, signal.SIGTERM):
            return
        if signal.getsignal(signum) != handlers.on_signal:
            return  # the program (or `zros bag`, or the launch supervisor) handles it itself
        with self._lock:
            if self._handling:
                _exit_now(128 + signum)   # a second signal while the first is being handled
            self._handling = True
            if handlers.cli_grace_s is not None:
                self._arm(handlers.cli_grace_s, 'cli')
                return
            self._settle()
        if handlers.stops_contexts(signum):
            _request_stop()
            threading.Thread(target=_shutdown_contexts, name='zros-signal-shutdown', daemon=True).start()
        threading.main_thread().join()
        # The interpreter is finalizing: joining threads, running atexit hooks, closing Zenoh.
        with self._lock:
            self._arm(EXIT_S, 'exit')

    def _arm(self, seconds: float, kind: str) -> None:
        """End the process `seconds` from now unless cancelled; works during finalization."""
        if self._devnull is None:
            self._devnull = open(os.devnull, 'w')
        faulthandler.dump_traceback_later(seconds, exit=True, file=self._devnull)
        self._armed = kind


_watch = _Watcher()
_installed: _Handlers | None = None


def _exit_now(code: int) -> None:
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except Exception:  # noqa: BLE001 - a closed or broken stream must not stop the exit
            pass
    os._exit(code)


def _request_stop() -> None:
    from zros.context import initialized_contexts
    for context in initialized_contexts():
        context._request_stop()


def _shutdown_contexts() -> None:
    from zros.context import initialized_contexts
    for context in initialized_contexts():
        try:
            context.shutdown()
        except Exception as exc:  # noqa: BLE001 - the other contexts must still go
            print(f'zros: shutdown after a signal failed: {exc}', file=sys.stderr)


def _install(options: SignalHandlerOptions, *, cli_grace_s: float | None) -> None:
    global _installed
    options = SignalHandlerOptions(options)
    if options == SignalHandlerOptions.NO or threading.current_thread() is not threading.main_thread():
        return  # Python lets only the main thread set signal handlers
    if _installed is not None:
        if _installed.options == options and _installed.cli_grace_s == cli_grace_s:
            return
        uninstall_signal_handlers()
    handlers = _Handlers(options, cli_grace_s=cli_grace_s)
    for signum in _SIGNALS[options]:
        handlers.previous[signum] = signal.signal(signum, handlers.on_signal)
    _installed = handlers
    _watch.start()


def signal_received() -> bool:
    """Whether a SIGINT or SIGTERM handled here has started ending the process."""
    return _watch._handling or _watch._main_saw is not None


def install_signal_handlers(options: SignalHandlerOptions = SignalHandlerOptions.ALL) -> None:
    """Handle SIGINT and/or SIGTERM as described in the module docstring (`zros.init()` calls
    this). Only the main thread can install handlers; elsewhere this does nothing."""
    _install(options, cli_grace_s=None)


def exit_on_signals(grace_s: float = 1.0) -> None:
    """For command-line tools: SIGINT and SIGTERM raise KeyboardInterrupt in the main thread,
    and the process exits at the latest `grace_s` after the signal."""
    _install(SignalHandlerOptions.ALL, cli_grace_s=grace_s)


def uninstall_signal_handlers() -> None:
    """Put back the handlers that were in place before (a no-op outside the main thread)."""
    global _installed
    handlers = _installed
    if handlers is None or threading.current_thread() is not threading.main_thread():
        return
    _installed = None
    for signum, previous in handlers.previous.items():
        if signal.getsignal(signum) == handlers.on_signal:
            signal.signal(signum, previous if previous is not None else signal.SIG_DFL)
    _watch.stop()


def get_current_signal_handlers_options() -> SignalHandlerOptions:
    return _installed.options if _installed is not None else SignalHandlerOptions.NO


def _after_fork_in_child() -> None:
    """A forked child has no watcher thread and must not write into its parent's pipe."""
    global _watch
    if _watch._write_fd >= 0:
        try:
            signal.set_wakeup_fd(-1)
        except ValueError:
            pass
    _watch = _Watcher()


os.register_at_fork(after_in_child=_after_fork_in_child)
