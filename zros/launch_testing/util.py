"""Finding the processes a test asks about: by the launch action that made them
(`process=talker_node`), by (part of) their name (`process='talker'`, which matches
`talker-1`), narrowed by command-line arguments, or all of them (`process=None`)."""
from __future__ import annotations

import sys
from typing import Any, NamedTuple

__all__ = ['ProcessDetails', 'NO_CMD_ARGS', 'NoMatchingProcessException', 'resolveProcesses', 'KeepAliveProc']

#: `cmd_args=NO_CMD_ARGS` matches a process started without arguments.
NO_CMD_ARGS = object()


class NoMatchingProcessException(Exception):
    """No process recorded so far matches what the test asked for."""


class ProcessDetails(NamedTuple):
    """A process of the launch: its name in the output (`talker-1`), the action that made it,
    and its command line."""

    name: str
    action: Any
    cmd: list


def _describe(details: ProcessDetails) -> str:
    return ' '.join([details.name, *details.cmd[1:]])


def _args_match(details: ProcessDetails, cmd_args: Any) -> bool:
    if cmd_args is None:
        return True
    if cmd_args is NO_CMD_ARGS:
        return len(details.cmd) == 1
    return all(arg in details.cmd[1:] for arg in ([cmd_args] if isinstance(cmd_args, str) else cmd_args))


def resolveProcesses(info_obj: Any, *, process: Any = None, cmd_args: Any = None,
                     strict_proc_matching: bool = True) -> list[str]:
    """The names of the processes of `info_obj` (proc_info or proc_output) that `process`
    and `cmd_args` select.

    Raises:
        NoMatchingProcessException: none does (yet).
        Exception: `process` is a name that matches several and `strict_proc_matching` is set.
        TypeError: `process` is neither None, a name, nor a launch action.
    """
    known: list[ProcessDetails] = info_obj.process_details()
    if process is None:
        if not known:
            raise NoMatchingProcessException('no process has been recorded yet')
        return [d.name for d in known]
    if isinstance(process, str):
        matches = [d.name for d in known if process in d.name and _args_match(d, cmd_args)]
        listing = ', '.join(sorted(_describe(d) for d in known)) or 'none'
        if not matches:
            raise NoMatchingProcessException(f"no process matches the name '{process}' and args {cmd_args!r} "
                                             f'(processes: {listing})')
        if strict_proc_matching and len(matches) > 1:
            raise Exception(f"several processes match the name '{process}' and args {cmd_args!r}: {listing}")
        return matches
    from zros.launch.action import Action
    if isinstance(process, Action):
        matches = [d.name for d in known if d.action is process]
        if not matches:
            raise NoMatchingProcessException(f'no process recorded for {process!r}')
        return matches
    raise TypeError(f"process must be a launch action (ExecuteProcess, Node) or a name, not {type(process).__name__}")


def KeepAliveProc() -> Any:
    """A process that does nothing until it is stopped: keeps a test's launch running while
    the tests run when every process under test ends on its own."""
    from zros.launch.actions.process import ExecuteProcess
    script = 'import time\ntry:\n    while True:\n        time.sleep(1)\nexcept KeyboardInterrupt:\n    pass\n'
    return ExecuteProcess(cmd=[sys.executable, '-c', script])
