"""Processes a test starts: zros nodes (`zros run`), launch files, any command. Each one's
output goes to a log file that the test can wait on, and every process (with its process
group) is stopped when the group is closed, so nothing outlives the test."""
from __future__ import annotations

import os
import signal
import subprocess
import sys
from pathlib import Path

from zros.process_group import kill_group
from zros.testing.waits import WaitTimeout, wait_until

__all__ = ['Child', 'ProcessGroup', 'kill_group']


class Child:
    """A started process; stdout and stderr go to one log file (`output()`)."""

    def __init__(self, argv: list[str], log: Path, env: dict[str, str], cwd: str | Path | None) -> None:
        self.argv = argv
        self.log = log
        self._log_handle = open(log, 'wb')
        self.popen = subprocess.Popen(argv, stdout=self._log_handle, stderr=subprocess.STDOUT,
                                      stdin=subprocess.DEVNULL, env=env, cwd=cwd, start_new_session=True)

    @property
    def pid(self) -> int:
        return self.popen.pid

    def output(self) -> str:
        return self.log.read_text(errors='replace')

    def wait_for_output(self, text: str, timeout: float = 10.0) -> str:
        """Until `text` appears in the output (returned whole); WaitTimeout, with the output so
        far, if it does not, or at once if the process exits without printing it."""
        def found() -> bool:
            if text in self.output():
                return True
            if self.popen.poll() is not None and text not in self.output():
                raise WaitTimeout(f'{self.argv} exited with {self.popen.returncode} before printing '
                                  f'{text!r}; output:\n{self.output()}')
            return False
        wait_until(found, timeout, message=lambda: f'{text!r} from {self.argv}; output so far:\n{self.output()}')
        return self.output()

    def signal(self, signum: int) -> None:
        self.popen.send_signal(signum)

    def wait(self, timeout: float) -> int:
        return self.popen.wait(timeout=timeout)

    def stop(self, timeout: float = 5.0) -> int | None:
        """Ctrl-C (SIGINT), then SIGKILL for the whole group after `timeout`; the exit status."""
        if self.popen.poll() is None:
            self.popen.send_signal(signal.SIGINT)
            try:
                self.popen.wait(timeout=timeout)
            except subprocess.TimeoutExpired:
                pass
        self.kill()
        return self.popen.returncode

    def kill(self) -> None:
        kill_group(self.popen)
        self._log_handle.close()


class ProcessGroup:
    """Starts processes in the current environment and kills them all (groups included) on
    `close()`.

    `group.run(pkg, exe, *args)` runs `zros run pkg exe`, `group.launch(file, *args)` runs
    `zros launch`, `group.script(text, *args)` a Python script written to disk, and
    `group.command(*argv)` anything.
    """

    def __init__(self, directory: Path, *, cwd: str | Path | None = None) -> None:
        self._dir = Path(directory)
        self._cwd = cwd
        self._children: list[Child] = []

    def command(self, *argv: str, name: str | None = None) -> Child:
        tag = name or Path(str(argv[-1])).name
        log = self._dir / f'child-{len(self._children) + 1}-{tag}.log'
        child = Child([str(a) for a in argv], log, dict(os.environ), self._cwd)
        self._children.append(child)
        return child

    __call__ = command

    def run(self, package: str, executable: str, *args: str) -> Child:
        return self.command(sys.executable, '-m', 'zros', 'run', package, executable, *args, name=executable)

    def launch(self, path: str | Path, *args: str) -> Child:
        return self.command(sys.executable, '-m', 'zros', 'launch', str(path), *args, name=Path(path).name)

    def script(self, text: str, *args: str, name: str = 'script') -> Child:
        path = self._dir / f'{name}-{len(self._children) + 1}.py'
        path.write_text(text)
        return self.command(sys.executable, str(path), *args, name=name)

    def close(self) -> None:
        for child in self._children:
            child.kill()
