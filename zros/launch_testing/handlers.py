"""What the tests see of the launch's processes: `proc_output` (every line they printed, per
process and in order) and `proc_info` (their starts and exits).

The runner records into the Active handlers from the supervisor's thread while the tests read
and wait on them from theirs; each Active handler wraps a plain one under a condition
variable, and the plain ones are what post-shutdown tests get (nothing changes any more).
"""
from __future__ import annotations

import threading
from typing import Any, Callable, Iterator, NamedTuple

from zros.launch_testing.tools import find_text, strip_ansi
from zros.launch_testing.util import NoMatchingProcessException, ProcessDetails, resolveProcesses

__all__ = ['ProcessIO', 'ProcessStarted', 'ProcessExited', 'IoHandler', 'ActiveIoHandler', 'ProcInfoHandler',
           'ActiveProcInfoHandler', 'STREAMS']

STREAMS = ('stderr', 'stdout', None)   # None: both


class ProcessIO(NamedTuple):
    """Lines one process printed on one stream (launch's ProcessIO event)."""

    process_name: str
    action: Any
    text: bytes
    fd: int               # 1 stdout, 2 stderr

    @property
    def from_stdout(self) -> bool:
        return self.fd == 1

    @property
    def from_stderr(self) -> bool:
        return self.fd == 2


class ProcessStarted(NamedTuple):
    action: Any
    process_name: str
    pid: int
    cmd: list
    returncode: None = None   # still running


class ProcessExited(NamedTuple):
    action: Any
    process_name: str
    pid: int
    cmd: list
    returncode: int


class _Processes:
    """The processes seen so far, by name (what resolveProcesses looks through)."""

    def __init__(self) -> None:
        self._details: dict[str, ProcessDetails] = {}

    def track(self, details: ProcessDetails) -> None:
        self._details.setdefault(details.name, details)

    def process_details(self) -> list[ProcessDetails]:
        return list(self._details.values())

    def processes(self) -> list:
        """The launch actions of the processes (launch_testing returns those)."""
        return [d.action for d in self._details.values()]

    def process_names(self) -> list[str]:
        return list(self._details)

    def _names_of(self, key: Any) -> list[str]:
        return [key] if isinstance(key, str) else resolveProcesses(self, process=key)


class IoHandler(_Processes):
    """Output of every process, in the order it arrived; `handler[process]` is one process's."""

    def __init__(self) -> None:
        super().__init__()
        self._sequence: list[ProcessIO] = []
        self._by_name: dict[str, list[ProcessIO]] = {}

    def append(self, io: ProcessIO) -> None:
        self._sequence.append(io)
        self._by_name.setdefault(io.process_name, []).append(io)

    def __iter__(self) -> Iterator[ProcessIO]:
        return iter(list(self._sequence))

    def __getitem__(self, key: Any) -> list[ProcessIO]:
        return [io for name in self._names_of(key) for io in self._by_name.get(name, [])]

    def text(self, name: str, stream: str | None) -> str:
        """All a process printed on `stream` ('stderr', 'stdout', None for both)."""
        return ''.join(io.text.decode(errors='replace') for io in self._by_name.get(name, [])
                       if stream is None or (io.fd == 2) == (stream == 'stderr'))


class ProcInfoHandler(_Processes):
    """The last event of every process: ProcessStarted, then ProcessExited (with `returncode`)."""

    def __init__(self) -> None:
        super().__init__()
        self._events: dict[str, ProcessStarted | ProcessExited] = {}

    def append(self, event: ProcessStarted | ProcessExited) -> None:
        self._events[event.process_name] = event

    def __iter__(self) -> Iterator[ProcessStarted | ProcessExited]:
        return iter(list(self._events.values()))

    def __getitem__(self, key: Any) -> ProcessStarted | ProcessExited:
        names = [n for n in self._names_of(key) if n in self._events]
        if not names:
            raise KeyError(key)
        return self._events[names[0]]


def _check_stream(stream: str | None) -> None:
    if stream not in STREAMS:
        raise ValueError(f"stream must be 'stderr', 'stdout' or None (both), not {stream!r}")


class _Active:
    """A plain handler under a condition variable: the recorder appends, tests wait."""

    def __init__(self, handler: Any) -> None:
        self._handler = handler
        self._changed = threading.Condition()

    def _record(self, change: Callable[[], None]) -> None:
        with self._changed:
            change()
            self._changed.notify_all()

    def _wait(self, predicate: Callable[[], bool], timeout: float) -> bool:
        with self._changed:
            return self._changed.wait_for(predicate, timeout)

    def track(self, details: ProcessDetails) -> None:
        self._record(lambda: self._handler.track(details))

    def append(self, item: Any) -> None:
        self._record(lambda: self._handler.append(item))

    def __iter__(self) -> Iterator:
        with self._changed:
            return iter(self._handler)

    def __getitem__(self, key: Any) -> Any:
        with self._changed:
            return self._handler[key]

    def processes(self) -> list:
        with self._changed:
            return self._handler.processes()

    def process_names(self) -> list[str]:
        with self._changed:
            return self._handler.process_names()

    def process_details(self) -> list[ProcessDetails]:
        with self._changed:
            return self._handler.process_details()


class ActiveIoHandler(_Active):
    """`proc_output` while the launch runs: `assertWaitFor(...)` waits for output to appear."""

    def __init__(self) -> None:
        super().__init__(IoHandler())
        self._io_handler = self._handler   # launch_testing's name for the plain handler

    def waitFor(self, expected_output: Any = None, process: Any = None, cmd_args: Any = None, *,
                strict_proc_matching: bool = True, output_filter: Callable[[str], str] | None = None,
                timeout: float = 10, strip_ansi_escape_sequences: bool = True, stream: str | None = 'stderr') -> bool:
        """Whether `expected_output` (a string, a regex or a list of them in order) appeared in
        `stream` of the selected processes (default: any process) within `timeout` seconds."""
        _check_stream(stream)
        if output_filter is not None and not callable(output_filter):
            raise ValueError('output_filter is not callable')

        def found() -> bool:
            try:
                names = resolveProcesses(self._handler, process=process, cmd_args=cmd_args,
                                         strict_proc_matching=strict_proc_matching)
            except NoMatchingProcessException:
                return False
            for name in names:
                text = self._handler.text(name, stream)
                text = strip_ansi(text) if strip_ansi_escape_sequences else text
                if find_text(expected_output, output_filter(text) if output_filter else text) is not None:
                    return True
            return False
        return self._wait(found, timeout)

    def assertWaitFor(self, expected_output: Any = None, process: Any = None, cmd_args: Any = None, *,
                      timeout: float = 10, stream: str | None = 'stderr', **kwargs: Any) -> None:
        """`waitFor`, failing the test (AssertionError) with what was awaited and what arrived."""
        if self.waitFor(expected_output, process, cmd_args, timeout=timeout, stream=stream, **kwargs):
            return
        where = 'stdout and stderr' if stream is None else stream
        with self._changed:
            known = self._handler.process_names()
            try:
                names = resolveProcesses(self._handler, process=process, cmd_args=cmd_args, strict_proc_matching=False)
            except NoMatchingProcessException:
                names = []
            tail = ''.join(self._handler.text(name, stream) for name in names).splitlines()[-5:]
        who = f'any of {", ".join(names)}' if names else (
            f'{process!r}, which matches no process (processes: {", ".join(known) or "none yet"})')
        raise AssertionError(f'timed out after {timeout:g} s waiting for {expected_output!r} on {where} of {who}'
                             + (''.join(f'\n    {line}' for line in tail) if tail else '; nothing printed there'))


class ActiveProcInfoHandler(_Active):
    """`proc_info` while the launch runs: wait for a process to start or to end."""

    def __init__(self) -> None:
        super().__init__(ProcInfoHandler())
        self._proc_info_handler = self._handler   # launch_testing's name for the plain handler

    def _wait_for_event(self, process: Any, cmd_args: Any, timeout: float, exited: bool) -> bool:
        def happened() -> bool:
            try:
                name = resolveProcesses(self._handler, process=process, cmd_args=cmd_args)[0]
            except NoMatchingProcessException:
                return False
            try:
                return not exited or isinstance(self._handler[name], ProcessExited)
            except KeyError:
                return False
        return self._wait(happened, timeout)

    def assertWaitForShutdown(self, process: Any, cmd_args: Any = None, *, timeout: float = 10) -> None:
        if not self._wait_for_event(process, cmd_args, timeout, True):
            raise AssertionError(f'timed out after {timeout:g} s waiting for process {process!r} to finish')

    def assertWaitForStartup(self, process: Any, cmd_args: Any = None, *, timeout: float = 10) -> None:
        if not self._wait_for_event(process, cmd_args, timeout, False):
            raise AssertionError(f'timed out after {timeout:g} s waiting for process {process!r} to start')
