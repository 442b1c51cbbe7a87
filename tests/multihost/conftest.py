"""Hosts for the multi-machine tests: Linux network namespaces joined by a bridge.

    zrosmh-<pid>-sw   the switch: a bridge `br0`, one veth port per host (v1, v2, v3)
    zrosmh-<pid>-h1   eth0 10.123.0.1/24  (the router's host)
    zrosmh-<pid>-h2   eth0 10.123.0.2/24  (the robot: talker, servers)
    zrosmh-<pid>-h3   eth0 10.123.0.3/24  (the laptop: listener, CLI)

Every address is configured here, inside namespaces this file creates, and IPv6 is off in them:
no packet of these tests reaches the machine's own network. Each namespace has its own
loopback, so the zros processes in it never meet the host's (or another test run's) hubs.
Needs root and iproute2; without them every test using `net` is skipped with the reason.
Namespaces, links and processes are removed at the end of the session, even on failure, and
left-overs of a crashed run (its pid is gone) are removed at the start of the next one.
"""
from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path
from typing import Callable

import pytest

from tools.link_netns import IP, ip as _ip, remove_namespace, remove_stale, unavailable_reason

REPO = Path(__file__).resolve().parents[2]
PREFIX = 'zrosmh'
SUBNET = '10.123.0'
HOSTS = ('h1', 'h2', 'h3')
ROUTER = f'{SUBNET}.1'

_SCRUBBED = ('ZROS_CONNECT', 'ZROS_LISTEN', 'ZROS_DISCOVERY', 'ZROS_CONFIG', 'ZROS_DOMAIN_ID', 'ROS_DOMAIN_ID',
             'ZROS_INTERFACE_PATH', 'ZROS_NODE_PATH', 'ZENOH_CONFIG', 'RCUTILS_CONSOLE_OUTPUT_FORMAT',
             'RCUTILS_LOGGING_USE_STDOUT')


class Proc:
    """A process running in one namespace, its own process group, output in a log file."""

    def __init__(self, argv: list[str], ns: str, log: Path, env: dict[str, str], cwd: Path) -> None:
        self.argv, self.ns, self.log = argv, ns, log
        self._handle = open(log, 'wb')
        self.popen = subprocess.Popen([IP, 'netns', 'exec', ns, *argv], stdout=self._handle,
                                      stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL, env=env, cwd=cwd,
                                      start_new_session=True)

    def output(self) -> str:
        return self.log.read_text(errors='replace')

    def alive(self) -> bool:
        return self.popen.poll() is None

    def wait_for(self, text: str, timeout: float = 15.0) -> str:
        deadline = time.monotonic() + timeout
        while True:
            out = self.output()
            if text in out:
                return out
            if self.popen.poll() is not None:
                pytest.fail(f'{self.argv} exited ({self.popen.returncode}) before printing {text!r}:\n{out}')
            if time.monotonic() > deadline:
                pytest.fail(f'no {text!r} from {self.argv} within {timeout} s; output:\n{out}')
            time.sleep(0.05)

    def kill(self) -> None:
        if self.popen.poll() is None:
            try:
                os.killpg(self.popen.pid, signal.SIGKILL)
            except (ProcessLookupError, PermissionError):
                pass
        try:
            self.popen.wait(timeout=5)
        except subprocess.TimeoutExpired:  # pragma: no cover - SIGKILL does not fail
            pass
        self._handle.close()


class Result:
    def __init__(self, argv: list[str], returncode: int, stdout: str, stderr: str, seconds: float) -> None:
        self.argv, self.returncode, self.stdout, self.stderr, self.seconds = argv, returncode, stdout, stderr, seconds

    def __repr__(self) -> str:
        return (f'<{" ".join(self.argv)}: exit {self.returncode} in {self.seconds:.2f} s\n--- stdout\n{self.stdout}'
                f'--- stderr\n{self.stderr}>')


class Host:
    def __init__(self, net: 'Net', name: str, index: int) -> None:
        self.net, self.name, self.index = net, name, index
        self.ns = f'{net.tag}-{name}'
        self.address = f'{SUBNET}.{index}'
        self.port = f'v{index}'          # this host's port on the switch

    def env(self, domain: int = 0, **extra: str | None) -> dict[str, str]:
        env = {k: v for k, v in os.environ.items() if k not in _SCRUBBED}
        env.update(ZROS_DOMAIN_ID=str(domain), PYTHONUNBUFFERED='1', RCUTILS_COLORIZED_OUTPUT='0')
        for key, value in extra.items():
            if value is None:
                env.pop(key, None)
            else:
                env[key] = value
        return env

    def spawn(self, *argv: str, name: str, domain: int = 0, cwd: Path | None = None, **env: str | None) -> Proc:
        return self.net.start(self, [str(a) for a in argv], name, self.env(domain, **env), cwd or REPO)

    def zros_bg(self, *args: str, name: str, domain: int = 0, cwd: Path | None = None, **env: str | None) -> Proc:
        """A long-running `zros ...` in this host (a node, a router, an echo)."""
        return self.spawn(sys.executable, '-m', 'zros.cli.main', *args, name=name, domain=domain, cwd=cwd, **env)

    def zros(self, *args: str, timeout: float = 20.0, domain: int = 0, cwd: Path | None = None,
             **env: str | None) -> Result:
        """Run `zros ARGS` in this host to completion (killed on timeout)."""
        argv = [sys.executable, '-m', 'zros.cli.main', *map(str, args)]
        started = time.monotonic()
        popen = subprocess.Popen([IP, 'netns', 'exec', self.ns, *argv], stdout=subprocess.PIPE,
                                 stderr=subprocess.PIPE, stdin=subprocess.DEVNULL, env=self.env(domain, **env),
                                 cwd=cwd or REPO, start_new_session=True)
        try:
            out, err = popen.communicate(timeout=timeout)
        except subprocess.TimeoutExpired:
            os.killpg(popen.pid, signal.SIGKILL)
            out, err = popen.communicate()
            pytest.fail(f'zros {" ".join(map(str, args))} in {self.name} did not finish within {timeout} s; '
                        f'stdout: {out.decode(errors="replace")!r} stderr: {err.decode(errors="replace")!r}')
        finally:
            try:
                os.killpg(popen.pid, signal.SIGKILL)
            except (ProcessLookupError, PermissionError):
                pass
        return Result(argv[3:], popen.returncode, out.decode(errors='replace'), err.decode(errors='replace'),
                      time.monotonic() - started)


class Net:
    """Three hosts on one switch. `net.h1`, `net.h2`, `net.h3`; `net.link(host, up)`."""

    def __init__(self, logs: Path) -> None:
        self.tag = f'{PREFIX}-{os.getpid()}'
        self.logs = logs
        self.switch = f'{self.tag}-sw'
        self.hosts = {name: Host(self, name, i + 1) for i, name in enumerate(HOSTS)}
        self._procs: list[Proc] = []
        self._count = 0
        self._namespaces: list[str] = []
        try:
            self._build()
        except BaseException:
            self.close()
            raise

    def __getattr__(self, name: str) -> Host:
        hosts = self.__dict__.get('hosts', {})
        if name in hosts:
            return hosts[name]
        raise AttributeError(name)

    def _add_namespace(self, ns: str) -> None:
        _ip('netns', 'add', ns)
        self._namespaces.append(ns)
        _ip('-n', ns, 'link', 'set', 'lo', 'up')
        # IPv4 only: no IPv6 link-local chatter, and the router's default (IPv4) is what is tested.
        subprocess.run([IP, 'netns', 'exec', ns, 'sh', '-c',
                        'for f in /proc/sys/net/ipv6/conf/all/disable_ipv6 /proc/sys/net/ipv6/conf/default/disable_ipv6;'
                        ' do [ -w $f ] && echo 1 > $f; done; true'], capture_output=True, timeout=20)

    def _build(self) -> None:
        self._add_namespace(self.switch)
        _ip('-n', self.switch, 'link', 'add', 'br0', 'type', 'bridge')
        _ip('-n', self.switch, 'link', 'set', 'br0', 'up')
        for host in self.hosts.values():
            self._add_namespace(host.ns)
            _ip('link', 'add', 'eth0', 'netns', host.ns, 'type', 'veth', 'peer', 'name', host.port,
                'netns', self.switch)
            _ip('-n', self.switch, 'link', 'set', host.port, 'master', 'br0')
            _ip('-n', self.switch, 'link', 'set', host.port, 'up')
            _ip('-n', host.ns, 'addr', 'add', f'{host.address}/24', 'dev', 'eth0')
            _ip('-n', host.ns, 'link', 'set', 'eth0', 'up')
            # Multicast scouting (ZROS_DISCOVERY=subnet) stays on this host's eth0, inside the switch.
            _ip('-n', host.ns, 'route', 'add', '224.0.0.0/4', 'dev', 'eth0')

    def start(self, host: Host, argv: list[str], name: str, env: dict[str, str], cwd: Path) -> Proc:
        self._count += 1
        proc = Proc(argv, host.ns, self.logs / f'{self._count:02d}-{host.name}-{name}.log', env, cwd)
        self._procs.append(proc)
        return proc

    def link(self, host: Host, up: bool) -> None:
        """Plug or unplug `host`'s cable at the switch."""
        _ip('-n', self.switch, 'link', 'set', host.port, 'up' if up else 'down')

    def kill_all(self, procs: list[Proc] | None = None) -> None:
        for proc in list(self._procs if procs is None else procs):
            proc.kill()
            if proc in self._procs:
                self._procs.remove(proc)

    def close(self) -> None:
        self.kill_all()
        for ns in reversed(self._namespaces):
            remove_namespace(ns)
        self._namespaces.clear()


@pytest.fixture(scope='session')
def net(tmp_path_factory: pytest.TempPathFactory) -> Net:
    reason = unavailable_reason()
    if reason:
        pytest.skip(reason)
    remove_stale(PREFIX)   # namespaces of a run that died without its finalizers
    network = Net(tmp_path_factory.mktemp('multihost-logs'))
    yield network
    network.close()


@pytest.fixture
def procs(net: Net) -> Net:
    """Processes a test starts are killed when it ends (those of module fixtures are not)."""
    before = set(map(id, net._procs))
    yield net
    net.kill_all([p for p in net._procs if id(p) not in before])


def wait_until(predicate: Callable[[], object], timeout: float, message: str | Callable[[], str]) -> object:
    deadline = time.monotonic() + timeout
    while True:
        value = predicate()
        if value:
            return value
        if time.monotonic() > deadline:
            pytest.fail(f'timed out after {timeout} s waiting for ' + (message() if callable(message) else message))
        time.sleep(0.05)
