"""Shared fixtures of zros's own suite, built on zros.testing (what users' tests get): an
isolated zros domain per test, child processes that always die, waits that always end.

Isolation: every test gets a domain id in 100..230 whose hub port (7447 + id) is free on
loopback, reserved with a lock file so parallel test runs on one machine never share one, and
set as ZROS_DOMAIN_ID for the test process and every child it starts. Settings that could send
traffic elsewhere (ZROS_CONNECT, ZROS_DISCOVERY, ZROS_CONFIG, ...) are removed for the test, and
so are a developer's search paths and log format (zros.testing.domains.ALL_SETTINGS).
"""
from __future__ import annotations

import contextlib
import os
import signal
import subprocess
import sys
import sysconfig
import threading
from pathlib import Path
from typing import Any, Callable, Iterator

import pytest

try:  # property-based tests: no per-example deadline (two cores shared with process tests would miss it)
    from hypothesis import settings as _hypothesis_settings
    _hypothesis_settings.register_profile('zros', deadline=None, print_blob=True)
    _hypothesis_settings.load_profile('zros')
except ImportError:
    pass

from zros.testing import DomainLock, ProcessGroup, spin_until, wait_until
from zros.testing.domains import ALL_SETTINGS, HUB_BASE_PORT, isolated_environment
from zros.testing.processes import kill_group

__all__ = ['REPO', 'wait_until', 'spin_until', 'run_cli', 'assert_clean_failure', 'CliResult', 'activate',
           'load_tool', 'int32_pair', 'spinning']

REPO = Path(__file__).resolve().parents[1]


def int32_pair(make_context: Callable[[], Any], topic: str, callback: Callable[..., Any], qos: Any = 10,
               group: Any = None, name: str = 'sub') -> tuple[Any, Any, Any, Any]:
    """(publisher, subscription, its node, a SingleThreadedExecutor with the node), matched: an
    Int32 subscription in a context of its own, its publisher in another."""
    from zros.executors import SingleThreadedExecutor
    from zros.node import Node

    from interfaces.std_msgs.msg import Int32
    pub_ctx, sub_ctx = make_context(), make_context()
    node = Node(name, context=sub_ctx)
    sub = node.create_subscription(Int32, topic, callback, qos, callback_group=group)
    executor = SingleThreadedExecutor(context=sub_ctx)
    executor.add_node(node)
    publisher = Node(f'{name}_pub', context=pub_ctx).create_publisher(Int32, topic, 10)
    assert publisher.wait_for_subscribers(1, 5.0)
    return publisher, sub, node, executor


def spinning(executor: Any, target: Callable[[], Any] | None = None,
             errors: list | None = None) -> threading.Thread:
    """A daemon thread running `target` (the executor's spin() by default), started; with
    `errors`, an exception out of it is appended there instead of ending the thread loudly."""
    def run() -> None:
        try:
            (target or executor.spin)()
        except Exception as exc:  # noqa: BLE001 - the test reads it
            if errors is None:
                raise
            errors.append(exc)
    thread = threading.Thread(target=run, daemon=True)
    thread.start()
    return thread


def load_tool(name: str) -> Any:
    """The module of the script tools/NAME.py (tools/ is not a package), for testing its functions."""
    import importlib.util
    spec = importlib.util.spec_from_file_location(name, REPO / 'tools' / f'{name}.py')
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture
def domain(monkeypatch: pytest.MonkeyPatch) -> int:
    """A private zros domain id for this test, exported as ZROS_DOMAIN_ID."""
    lock = DomainLock()
    isolated_environment(monkeypatch, lock.domain, ALL_SETTINGS)
    yield lock.domain
    lock.close()


@pytest.fixture(scope='module')
def module_domain() -> int:
    """Like `domain`, shared by the tests of one module (for a module-wide node process)."""
    lock = DomainLock()
    with pytest.MonkeyPatch.context() as mp:
        isolated_environment(mp, lock.domain, ALL_SETTINGS)
        yield lock.domain
    lock.close()


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


@pytest.fixture
def fresh_venv(tmp_path: Path) -> Path:
    """A new venv that sees this checkout's zros and its dependencies (through a .pth file, so
    nothing is downloaded) and nothing else; returns its python."""
    venv = tmp_path / 'venv'
    subprocess.run([sys.executable, '-m', 'venv', venv], check=True, timeout=120)
    python = venv / 'bin' / 'python'
    purelib = subprocess.run([python, '-c', 'import sysconfig; print(sysconfig.get_paths()["purelib"])'],
                             capture_output=True, text=True, check=True).stdout.strip()
    (Path(purelib) / 'zros_under_test.pth').write_text(f"{REPO}\n{sysconfig.get_paths()['purelib']}\n")
    return python


# -- child processes --------------------------------------------------------------------------
class Spawner(ProcessGroup):
    """zros.testing's ProcessGroup, run from the repository; `spawn.node(pkg, exe)` is `run`."""

    node = ProcessGroup.run


@pytest.fixture
def spawn(tmp_path: Path, domain: int) -> Spawner:
    """Child processes in the test's domain, killed (with their process groups) at teardown."""
    spawner = Spawner(tmp_path, cwd=REPO)
    yield spawner
    spawner.close()


@pytest.fixture(scope='module')
def module_spawn(tmp_path_factory: pytest.TempPathFactory, module_domain: int) -> Spawner:
    """Like `spawn`, for children shared by a module's tests (in `module_domain`)."""
    spawner = Spawner(tmp_path_factory.mktemp('children'), cwd=REPO)
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
        kill_group(popen)
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


@pytest.fixture
def probe(make_context: Callable[[], Any]) -> Any:
    """A node named `probe` in its own context, spun by a SingleThreadedExecutor on a daemon
    thread (the test thread publishes and waits); the executor stops at teardown."""
    import threading

    from zros.executors import ExternalShutdownException, SingleThreadedExecutor
    from zros.node import Node
    node = Node('probe', context=make_context())
    executor = SingleThreadedExecutor(context=node.context)
    executor.add_node(node)

    def spin() -> None:
        with contextlib.suppress(ExternalShutdownException):
            executor.spin()
    threading.Thread(target=spin, daemon=True).start()
    yield node
    executor.shutdown(timeout_sec=1)


def activate(node: Any, target: str, child: Any) -> None:
    """Configure then activate the lifecycle node `target` (run by the process `child`) as a
    lifecycle manager would; the test fails with the child's output if it cannot."""
    from zros.lifecycle import LifecycleClient
    lifecycle = LifecycleClient(node, target)
    assert lifecycle.wait_for_services(timeout_sec=15), child.output()
    assert lifecycle.change_state('configure', timeout_sec=10), child.output()
    assert lifecycle.change_state('activate', timeout_sec=10), child.output()


@contextlib.contextmanager
def background_node(name: str) -> Iterator[Any]:
    """A node in its own context, spun by a MultiThreadedExecutor on a daemon thread (for pages
    and servers that answer while the test thread drives a browser); shut down on exit."""
    import threading

    from zros.context import Context
    from zros.executors import ExternalShutdownException, MultiThreadedExecutor
    from zros.node import Node
    ctx = Context().init([], install_signal_handlers=False)
    node = Node(name, context=ctx)
    executor = MultiThreadedExecutor(context=ctx)
    executor.add_node(node)

    def spin() -> None:
        try:
            executor.spin()
        except ExternalShutdownException:
            pass
    threading.Thread(target=spin, daemon=True).start()
    try:
        yield node
    finally:
        executor.shutdown(timeout_sec=2)
        ctx.shutdown()
