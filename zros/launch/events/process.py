"""Process events (launch.events.process): a process the launch runs started, printed, or
exited.

The supervisor (zros.launch.supervisor) reports what its processes do; these are the events
handlers receive for it: OnProcessStart's ProcessStarted, OnProcessExit's ProcessExited,
OnProcessIO's ProcessIO (stdout/stderr lines, `fd` 1 or 2).
"""
from __future__ import annotations

from typing import Any

from zros.launch.event import Event

__all__ = ['RunningProcessEvent', 'ProcessStarted', 'ProcessExited', 'ProcessIO', 'ProcessStdin',
           'ProcessStdout', 'ProcessStderr']


class RunningProcessEvent(Event):
    """What every process event tells: the action that made the process, the process's name
    (`talker-1`), its command line, working directory, environment and pid."""

    name = 'launch.events.process.RunningProcessEvent'

    def __init__(self, *, action: Any, name: str, cmd: list, cwd: str | None, env: dict | None,
                 pid: int) -> None:
        self.action, self.process_name, self.cmd = action, name, list(cmd)
        self.cwd, self.env, self.pid = cwd, env, pid

    @property
    def execute_process_action(self) -> Any:
        return self.action

    def __repr__(self) -> str:
        return f'<{type(self).__name__} {self.process_name} pid={self.pid}>'


class ProcessStarted(RunningProcessEvent):
    name = 'launch.events.process.ProcessStarted'


class ProcessExited(RunningProcessEvent):
    """The process exited with `returncode` (negative: killed by that signal)."""

    name = 'launch.events.process.ProcessExited'

    def __init__(self, *, returncode: int, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.returncode = returncode


class ProcessIO(RunningProcessEvent):
    """`text` (bytes) the process read (`fd` 0) or wrote (1: stdout, 2: stderr)."""

    name = 'launch.events.process.ProcessIO'

    def __init__(self, *, text: bytes, fd: int, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.text = text
        self.fd = fd


class ProcessStdin(ProcessIO):
    name = 'launch.events.process.ProcessStdin'

    def __init__(self, **kwargs: Any) -> None:
        super().__init__(fd=0, **kwargs)


class ProcessStdout(ProcessIO):
    name = 'launch.events.process.ProcessStdout'

    def __init__(self, **kwargs: Any) -> None:
        super().__init__(fd=1, **kwargs)


class ProcessStderr(ProcessIO):
    name = 'launch.events.process.ProcessStderr'

    def __init__(self, **kwargs: Any) -> None:
        super().__init__(fd=2, **kwargs)
