"""Robot and laptop in two network namespaces whose only path is tools/link_shaper.py.

    <tag>-robot    eth0 10.77.1.1/24     the robot's processes dial the link at 10.77.1.254
    <tag>-mid      to_robot 10.77.1.254/24, to_laptop 10.77.2.254/24: the shaper, and no IP forwarding, so
                   nothing reaches the other side except through it
    <tag>-laptop   eth0 10.77.2.1/24     the Zenoh router and the laptop's processes

The robot is a Zenoh client of the laptop's router (`ROBOT_CONNECT`), as docs/multi-machine.md
sets up a robot on Wi-Fi: every byte between the two sides is one TCP connection through the
shaper. Used by tests/multihost/test_link.py and benchmarks/link.py; needs root and iproute2
(`unavailable_reason()` says why not). Namespaces and processes go at `close()`, and those of a
run that died (its pid is gone) at the next `Topology()`.
"""
from __future__ import annotations

import os
import shutil
import signal
import subprocess
import sys
from pathlib import Path

__all__ = ['Topology', 'IP', 'ip', 'unavailable_reason', 'remove_namespace', 'remove_stale', 'ROBOT_ADDRESS', 'LAPTOP_ADDRESS', 'LINK_ADDRESS', 'ROBOT_CONNECT',
           'SHAPER']

PREFIX = 'zroslink'
ROBOT_ADDRESS, LINK_ADDRESS = '10.77.1.1', '10.77.1.254'
LAPTOP_ADDRESS, LINK_LAPTOP_ADDRESS = '10.77.2.1', '10.77.2.254'
ROUTER_PORT = 7447
#: what the robot's processes put in ZROS_CONNECT: the shaper's end of the link
ROBOT_CONNECT = f'tcp/{LINK_ADDRESS}:{ROUTER_PORT}'
SHAPER = Path(__file__).resolve().parent / 'link_shaper.py'
IP = shutil.which('ip') or '/usr/sbin/ip'


def ip(*args: str, check: bool = True) -> str:
    """Run iproute2's `ip ARGS`; its output, or RuntimeError with its message (unless not `check`)."""
    done = subprocess.run([IP, *args], capture_output=True, text=True, timeout=20)
    if check and done.returncode:
        raise RuntimeError(f'ip {" ".join(args)}: {done.stderr.strip()}')
    return done.stdout


def unavailable_reason() -> str | None:
    """Why namespaces, veth pairs and bridges cannot be built here (tried once, then removed),
    or None."""
    if not sys.platform.startswith('linux'):
        return 'network namespaces need Linux'
    if os.geteuid() != 0:
        return 'needs root to create network namespaces, veth pairs and bridges'
    if not os.path.exists(IP):
        return 'needs iproute2 (the ip command)'
    probe = f'{PREFIX}-{os.getpid()}-probe'
    try:
        ip('netns', 'add', probe)
        ip('-n', probe, 'link', 'add', 'br0', 'type', 'bridge')
        ip('-n', probe, 'link', 'add', 'p0', 'type', 'veth', 'peer', 'name', 'p1')
    except (RuntimeError, OSError, subprocess.TimeoutExpired) as exc:
        return f'cannot create network namespaces, bridges or veth pairs here: {exc}'
    finally:
        ip('netns', 'del', probe, check=False)
    return None


def remove_namespace(ns: str) -> None:
    """Kill what still runs in `ns` (the namespace is its creator's), then delete it."""
    for pid in ip('netns', 'pids', ns, check=False).split():
        try:
            os.kill(int(pid), signal.SIGKILL)
        except (ProcessLookupError, ValueError):
            pass
    ip('netns', 'del', ns, check=False)


def remove_stale(prefix: str) -> None:
    """Delete the namespaces `<prefix>-<pid>-*` whose creating process `<pid>` is gone (a run
    that died without cleaning up)."""
    for line in ip('netns', 'list', check=False).splitlines():
        name = (line.split() or [''])[0]
        parts = name.split('-')
        if len(parts) == 3 and parts[0] == prefix and parts[1].isdigit() and not _alive(int(parts[1])):
            remove_namespace(name)


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        pass
    return True


class Topology:
    """The three namespaces, and the processes started in them (`spawn`), until `close()`."""

    def __init__(self, logs: Path) -> None:
        self.tag = f'{PREFIX}-{os.getpid()}'
        self.logs = logs
        self.robot, self.mid, self.laptop = (f'{self.tag}-{n}' for n in ('robot', 'mid', 'laptop'))
        self._namespaces: list[str] = []
        self._procs: list[subprocess.Popen] = []
        remove_stale(PREFIX)
        try:
            self._build()
        except BaseException:
            self.close()
            raise

    def _build(self) -> None:
        for ns in (self.robot, self.mid, self.laptop):
            ip('netns', 'add', ns)
            self._namespaces.append(ns)
            ip('-n', ns, 'link', 'set', 'lo', 'up')
            subprocess.run([IP, 'netns', 'exec', ns, 'sysctl', '-qw', 'net.ipv6.conf.all.disable_ipv6=1'],
                           capture_output=True, timeout=20)
        for ns, end, address, mid_end, mid_address in ((self.robot, 'eth0', ROBOT_ADDRESS, 'to_robot', LINK_ADDRESS),
                                                       (self.laptop, 'eth0', LAPTOP_ADDRESS, 'to_laptop', LINK_LAPTOP_ADDRESS)):
            ip('link', 'add', end, 'netns', ns, 'type', 'veth', 'peer', 'name', mid_end, 'netns', self.mid)
            ip('-n', ns, 'addr', 'add', f'{address}/24', 'dev', end)
            ip('-n', self.mid, 'addr', 'add', f'{mid_address}/24', 'dev', mid_end)
            ip('-n', ns, 'link', 'set', end, 'up')
            ip('-n', self.mid, 'link', 'set', mid_end, 'up')

    def spawn(self, ns: str, argv: list[str], name: str, env: dict[str, str] | None = None,
              cwd: Path | None = None) -> subprocess.Popen:
        """Start `argv` in namespace `ns`, its own process group, output in `<logs>/<name>.log`."""
        log = open(self.logs / f'{name}.log', 'wb')
        proc = subprocess.Popen([IP, 'netns', 'exec', ns, *map(str, argv)], stdout=log, stderr=subprocess.STDOUT,
                                stdin=subprocess.DEVNULL, env=env, cwd=cwd, start_new_session=True)
        log.close()
        proc.log = self.logs / f'{name}.log'   # type: ignore[attr-defined]
        self._procs.append(proc)
        return proc

    def start_shaper(self, control: Path, *options: str) -> subprocess.Popen:
        """The shaper in the middle namespace: the robot side's router port to the laptop's router."""
        return self.spawn(self.mid, [sys.executable, SHAPER, '--control', control, '--forward',
                                     f'{LINK_ADDRESS}:{ROUTER_PORT}={LAPTOP_ADDRESS}:{ROUTER_PORT}', *options],
                          'shaper')

    def stop(self, proc: subprocess.Popen) -> None:
        if proc.poll() is None:
            try:
                os.killpg(proc.pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
        proc.wait(timeout=10)
        if proc in self._procs:
            self._procs.remove(proc)

    def close(self) -> None:
        for proc in list(self._procs):
            self.stop(proc)
        for ns in reversed(self._namespaces):
            remove_namespace(ns)
        self._namespaces.clear()

    def __enter__(self) -> 'Topology':
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
