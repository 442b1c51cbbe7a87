"""`launch_testing.asserts`: checks on what the processes printed and how they ended, for
active tests (`proc_output`, `proc_info` while running) and post-shutdown tests alike."""
from __future__ import annotations

from contextlib import contextmanager
from typing import Any, Callable, Iterator

from zros.launch_testing.tools import find_text, strip_ansi
from zros.launch_testing.util import NO_CMD_ARGS, resolveProcesses

__all__ = ['assertExitCodes', 'assertInStream', 'assertInStdout', 'assertInStderr', 'assertDefaultStream',
           'assertSequentialStdout', 'SequentialTextChecker', 'NO_CMD_ARGS', 'EXIT_OK', 'EXIT_SIGINT',
           'EXIT_SIGQUIT', 'EXIT_SIGKILL', 'EXIT_SIGSEGV']

EXIT_OK = 0
EXIT_SIGINT = 130
EXIT_SIGQUIT = 131
EXIT_SIGKILL = 137
EXIT_SIGSEGV = 139


def _plain(handler: Any) -> Any:
    """The plain handler behind an Active one (asserts read a snapshot, not a moving target)."""
    return getattr(handler, '_handler', handler)


def assertExitCodes(proc_info: Any, allowable_exit_codes: list[int] = [EXIT_OK], process: Any = None,  # noqa: B006
                    cmd_args: Any = None, *, strict_proc_matching: bool = True) -> None:
    """Every selected process (default: all) ended with one of `allowable_exit_codes`."""
    for code in allowable_exit_codes:
        if not isinstance(code, int):
            raise AssertionError(f'Provided exit code {code!r} is not an int')
    info = _plain(proc_info)
    for name in resolveProcesses(info, process=process, cmd_args=cmd_args, strict_proc_matching=strict_proc_matching):
        returncode = info[name].returncode
        if returncode not in allowable_exit_codes:
            state = 'is still running' if returncode is None else f'exited with code {returncode}'
            raise AssertionError(f'Proc {name} {state} (allowed: {", ".join(map(str, allowable_exit_codes))})')


def assertInStream(proc_output: Any, expected_output: Any, process: Any, cmd_args: Any = None, *,
                   output_filter: Callable[[str], str] | None = None, strict_proc_matching: bool = True,
                   strip_ansi_escape_sequences: bool = True, stream: str = 'stderr') -> None:
    """`expected_output` is in what one of the selected processes printed on `stream`."""
    if stream not in ('stderr', 'stdout'):
        raise ValueError("Invalid value for stream; must be 'stdout' or 'stderr'")
    output = _plain(proc_output)
    names = resolveProcesses(output, process=process, cmd_args=cmd_args, strict_proc_matching=strict_proc_matching)
    for name in names:
        text = output.text(name, stream)
        text = strip_ansi(text) if strip_ansi_escape_sequences else text
        if find_text(expected_output, output_filter(text) if output_filter else text) is not None:
            return
    raise AssertionError(f"Did not find {expected_output!r} in {stream} of any of the matching processes: "
                         f"{', '.join(sorted(names))}")


def assertInStdout(proc_output: Any, expected_output: Any, process: Any, cmd_args: Any = None, **kwargs: Any) -> None:
    assertInStream(proc_output, expected_output, process, cmd_args, stream='stdout', **kwargs)


def assertInStderr(proc_output: Any, expected_output: Any, process: Any, cmd_args: Any = None, **kwargs: Any) -> None:
    assertInStream(proc_output, expected_output, process, cmd_args, stream='stderr', **kwargs)


def assertDefaultStream() -> str:
    """The stream assertInStream and assertWaitFor read by default (ROS logs to stderr)."""
    return 'stderr'


class SequentialTextChecker:
    """Finds texts in a process's output one after another (`assertInStdout(text)`)."""

    def __init__(self, output: str) -> None:
        self._output = output
        self._position = 0

    def assertInStdout(self, text: Any) -> None:
        span = find_text(text, self._output, self._position)
        if span is None:
            near = self._output[max(0, self._position - 200):self._position + 200]
            raise AssertionError(f'{text!r} not found in sequence after the previous match; output near it:\n{near}')
        self._position = span[1]

    assertInText = assertInStdout


@contextmanager
def assertSequentialStdout(proc_output: Any, process: Any, cmd_args: Any = None) -> Iterator[SequentialTextChecker]:
    """`with assertSequentialStdout(proc_output, proc) as cm: cm.assertInStdout('a')` ...: the
    texts appear in this order in everything that one process printed."""
    output = _plain(proc_output)
    name = resolveProcesses(output, process=process, cmd_args=cmd_args, strict_proc_matching=True)[0]
    yield SequentialTextChecker(''.join(io.text.decode(errors='replace') for io in output[name]))
