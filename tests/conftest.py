"""Shared fixtures: an isolated zros domain per test, child processes that always die, waits
that always end.

Isolation: every test gets a domain id in 100..230 whose hub port (7447 + id) is free on
loopback, reserved with a lock file so parallel test runs on one machine never share one, and
set as ZROS_DOMAIN_ID for the test process and every child it starts. Settings that could send
traffic elsewhere (ZROS_CONNECT, ZROS_DISCOVERY, ZROS_CONFIG, ...) are removed for the test.
"""
from __future__ import annotations

import fcntl
import os
import random
import signal
import socket
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any, Callable

import pytest

REPO = Path(__file__).resolve().parents[1]
HUB_BASE_PORT = 7447
DOMAIN_RANGE = (100, 230)

# Environment that must not leak from a developer's shell into the tests.
_SCRUBBED = ('ZROS_CONNECT', 'ZROS_LISTEN', 'ZROS_DISCOVERY', 'ZROS_CONFIG', 'ROS_DOMAIN_ID',
             'ZROS_INTERFACE_PATH', 'ZROS_NODE_PATH', 'RCUTILS_CONSOLE_OUTPUT_FORMAT',
             'RCUTILS_LOGGING_USE_STDOUT', 'ZENOH_CONFIG', 'ZROS_MAX_MESSAGE_SIZE', 'ZROS_MAX_REQUEST_SIZE', 'ZROS_SHM_POOL_SIZE',
             'ROS_SECURITY_ENABLE', 'ROS_SECURITY_KEYSTORE', 'ROS_SECURITY_STRATEGY', 'ROS_SECURITY_ENCLAVE_OVERRIDE')


def _port_free(port: int) -> bool:
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as probe:
        try:
            probe.bind(('127.0.0.1', port))
        except OSError:
            return False
    return True


class _DomainLock:
    """Holds one domain id for the life of a test (an flock'ed file, released on close)."""

    def __init__(self) -> None:
        lock_dir = Path(tempfile.gettempdir()) / 'zros-test-domains'
        lock_dir.mkdir(exist_ok=True)
        candidates = list(range(DOMAIN_RANGE[0], DOMAIN_RANGE[1] + 1))
        random.shuffle(candidates)
        for domain in candidates:
            if not _port_free(HUB_BASE_PORT + domain):
                continue
            handle = open(lock_dir / f'{domain}.lock', 'w')
            try:
                fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except OSError:
                handle.close()
                continue
            self.domain, self._handle = domain, handle
            return
        raise RuntimeError('no free zros test domain in 100..230')

    def close(self) -> None:
        self._handle.close()


def _isolate(mp: pytest.MonkeyPatch, domain: int) -> None:
    for name in _SCRUBBED:
        mp.delenv(name, raising=False)
    mp.setenv('ZROS_DOMAIN_ID', str(domain))
    mp.setenv('RCUTILS_COLORIZED_OUTPUT', '0')
    mp.setenv('PYTHONUNBUFFERED', '1')


@pytest.fixture
def domain(monkeypatch: pytest.MonkeyPatch) -> int:
    """A private zros domain id for this test, exported as ZROS_DOMAIN_ID."""
    lock = _DomainLock()
    _isolate(monkeypatch, lock.domain)
    yield lock.domain
    lock.close()


@pytest.fixture(scope='module')
def module_domain() -> int:
    """Like `domain`, shared by the tests of one module (for a module-wide node process)."""
    lock = _DomainLock()
    with pytest.MonkeyPatch.context() as mp:
        _isolate(mp, lock.domain)
        yield lock.domain
    lock.close()


# -- waiting ----------------------------------------------------------------------------------
def wait_until(predicate: Callable[[], Any], timeout: float, *, interval: float = 0.02,
               message: str | Callable[[], str] = 'condition') -> Any:
    """Poll `predicate` until it returns something truthy (returned) or fail after `timeout`."""
    deadline = time.monotonic() + timeout
    while True:
        value = predicate()
        if value:
            return value
        if time.monotonic() >= deadline:
            text = message() if callable(message) else message
            pytest.fail(f'timed out after {timeout} s waiting for {text}')
        time.sleep(interval)


def spin_until(executor: Any, predicate: Callable[[], Any], timeout: float, *,
               message: str | Callable[[], str] = 'condition') -> Any:
    """Spin `executor` (one callback at a time) until `predicate()` holds, or fail."""
    deadline = time.monotonic() + timeout
    while True:
        value = predicate()
        if value:
            return value
        remaining = deadline - time.monotonic()
        if remaining <= 0:
            text = message() if callable(message) else message
            pytest.fail(f'timed out after {timeout} s waiting for {text}')
        executor.spin_once(timeout_sec=min(0.05, remaining))


@pytest.fixture
def wait_for() -> Callable[..., Any]:
    """`wait_for(predicate, timeout=5, message=...)`: poll until truthy, else fail the test."""
    def wait(predicate: Callable[[], Any], timeout: float = 5.0, **kwargs: Any) -> Any:
        return wait_until(predicate, timeout, **kwargs)
    return wait


@pytest.fixture
def spin_for() -> Callable[..., Any]:
    """`spin_for(executor, predicate, timeout=5)`: spin until truthy, else fail the test."""
    def spin(executor: Any, predicate: Callable[[], Any], timeout: float = 5.0, **kwargs: Any) -> Any:
        return spin_until(executor, predicate, timeout, **kwargs)
    return spin


# -- child processes --------------------------------------------------------------------------
def _kill_group(popen: subprocess.Popen) -> None:
    try:
        os.killpg(popen.pid, signal.SIGKILL)
    except (ProcessLookupError, PermissionError):
        pass
    try:
        popen.wait(timeout=5)
    except subprocess.TimeoutExpired:  # pragma: no cover - SIGKILL does not fail
        pass


class Child:
    """A process started by the `spawn` fixture; stdout and stderr go to one log file."""

    def __init__(self, argv: list[str], log: Path, env: dict[str, str]) -> None:
        self.argv = argv
        self.log = log
        self._log_handle = open(log, 'wb')
        self.popen = subprocess.Popen(argv, stdout=self._log_handle, stderr=subprocess.STDOUT,
                                      stdin=subprocess.DEVNULL, env=env, cwd=REPO,
                                      start_new_session=True)

    @property
    def pid(self) -> int:
        return self.popen.pid

    def output(self) -> str:
        return self.log.read_text(errors='replace')

    def wait_for_output(self, text: str, timeout: float = 10.0) -> str:
        def found() -> bool:
            if text in self.output():
                return True
            if self.popen.poll() is not None and text not in self.output():
                pytest.fail(f'{self.argv} exited with {self.popen.returncode} before printing '
                            f'{text!r}; output:\n{self.output()}')
            return False
        wait_until(found, timeout, interval=0.02,
                   message=lambda: f'{text!r} from {self.argv}; output so far:\n{self.output()}')
        return self.output()

    def signal(self, signum: int) -> None:
        self.popen.send_signal(signum)

    def wait(self, timeout: float) -> int:
        return self.popen.wait(timeout=timeout)

    def kill(self) -> None:
        _kill_group(self.popen)
        self._log_handle.close()


class Spawner:
    """Starts children in the current environment and kills them all (groups included) on close.

    `spawner(*argv, name=None)` runs any command; `spawner.node(pkg, exe, *args)` runs
    `zros run pkg exe`; `spawner.script(text, *args)` runs a Python script written to disk."""

    def __init__(self, directory: Path) -> None:
        self._dir = directory
        self._children: list[Child] = []
        self._count = 0

    def _next(self) -> int:
        self._count += 1
        return self._count

    def __call__(self, *argv: str, name: str | None = None) -> Child:
        tag = name or Path(str(argv[-1])).name
        log = self._dir / f'child-{self._next()}-{tag}.log'
        child = Child([str(a) for a in argv], log, dict(os.environ))
        self._children.append(child)
        return child

    def node(self, package: str, executable: str, *args: str) -> Child:
        return self(sys.executable, '-m', 'zros.cli.main', 'run', package, executable, *args, name=executable)

    def script(self, text: str, *args: str, name: str = 'script') -> Child:
        path = self._dir / f'{name}-{self._next()}.py'
        path.write_text(text)
        return self(sys.executable, str(path), *args, name=name)

    def close(self) -> None:
        for child in self._children:
            child.kill()


@pytest.fixture
def spawn(tmp_path: Path, domain: int) -> Spawner:
    """Child processes in the test's domain, killed (with their process groups) at teardown."""
    spawner = Spawner(tmp_path)
    yield spawner
    spawner.close()


@pytest.fixture(scope='module')
def module_spawn(tmp_path_factory: pytest.TempPathFactory, module_domain: int) -> Spawner:
    """Like `spawn`, for children shared by a module's tests (in `module_domain`)."""
    spawner = Spawner(tmp_path_factory.mktemp('children'))
    yield spawner
    spawner.close()


class CliResult:
    def __init__(self, argv: list[str], returncode: int, stdout: str, stderr: str) -> None:
        self.argv, self.returncode, self.stdout, self.stderr = argv, returncode, stdout, stderr

    def __repr__(self) -> str:
        return (f'<zros {" ".join(self.argv)}: exit {self.returncode}\n--- stdout\n{self.stdout}'
                f'--- stderr\n{self.stderr}>')


def run_cli(*args: str, timeout: float = 15.0, env: dict[str, str] | None = None) -> CliResult:
    """Run `python -m zros.cli.main ARGS` to completion (killed, group and all, on timeout)."""
    argv = [sys.executable, '-m', 'zros.cli.main', *map(str, args)]
    popen = subprocess.Popen(argv, stdout=subprocess.PIPE, stderr=subprocess.PIPE, stdin=subprocess.DEVNULL,
                             env=dict(os.environ) if env is None else env, cwd=REPO,
                             start_new_session=True)
    try:
        out, err = popen.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        _kill_group(popen)
        out, err = popen.communicate()
        pytest.fail(f'zros {" ".join(map(str, args))} did not finish within {timeout} s; '
                    f'stdout: {out.decode(errors="replace")!r} stderr: {err.decode(errors="replace")!r}')
    finally:
        try:
            os.killpg(popen.pid, signal.SIGKILL)  # anything the command left behind
        except (ProcessLookupError, PermissionError):
            pass
    return CliResult(list(map(str, args)), popen.returncode, out.decode(errors='replace'),
                     err.decode(errors='replace'))


def assert_clean_failure(result, *fragments: str) -> str:
    """A failing command: non-zero exit, exactly one line on stderr naming the problem."""
    assert result.returncode != 0, result
    assert 'Traceback' not in result.stderr + result.stdout, result
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1, result
    for fragment in fragments:
        assert fragment in lines[0], result
    return lines[0]


@pytest.fixture
def zros_cli() -> Callable[..., CliResult]:
    """`zros_cli('topic', 'list', '-t')` runs the CLI in the test's environment."""
    return run_cli


# -- in-process contexts ---------------------------------------------------------------------
@pytest.fixture
def make_context(domain: int) -> Callable[[], Any]:
    """`make_context()` returns a new initialized zros Context (its own Zenoh session) in the
    test's domain; every one is shut down at teardown."""
    from zros.context import Context
    contexts = []

    def make() -> Any:
        ctx = Context().init([], install_signal_handlers=False)
        contexts.append(ctx)
        return ctx
    yield make
    for ctx in reversed(contexts):
        ctx.shutdown()


@pytest.fixture
def context(make_context: Callable[[], Any]) -> Any:
    """One initialized zros Context in the test's domain."""
    return make_context()


@pytest.fixture
def raw_session(domain: int) -> Any:
    """A plain zenoh-python session (no zros code) joining the test domain's hub on loopback,
    as a stranger's client would (docs/protocol.md); closed at teardown."""
    import json
    import zenoh
    config = zenoh.Config()
    config.insert_json5('mode', '"peer"')
    config.insert_json5('scouting/multicast/enabled', 'false')
    config.insert_json5('listen/endpoints', json.dumps(['tcp/127.0.0.1:0']))
    config.insert_json5('connect/endpoints', json.dumps([f'tcp/127.0.0.1:{HUB_BASE_PORT + domain}']))
    session = zenoh.open(config)
    yield session
    session.close()


@pytest.fixture
def log_records() -> list:
    """Every log record emitted in this process during the test: (severity, logger, text)."""
    from zros.logging import add_sink, remove_sink
    records = []

    def sink(severity, name, message, time_ns, file, function, line):
        records.append((int(severity), name, message))
    add_sink(sink)
    yield records
    remove_sink(sink)
