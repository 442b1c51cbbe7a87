"""A private zros domain per test: a domain id whose discovery port is free, held with a lock
file so parallel test runs on one machine never share one, and an environment without the
settings that could send traffic elsewhere."""
from __future__ import annotations

import fcntl
import os
import random
import tempfile
from contextlib import contextmanager
from pathlib import Path
from typing import IO, Iterator

from zros.config import HUB_BASE_PORT, hub_port_free

__all__ = ['DomainLock', 'isolated_environment', 'isolated_domain', 'DOMAIN_RANGE', 'HUB_BASE_PORT', 'NETWORK_SETTINGS', 'ALL_SETTINGS']

DOMAIN_RANGE = (100, 230)

#: Settings that could send a test's traffic elsewhere: never inherited by a test.
NETWORK_SETTINGS = ('ZROS_CONNECT', 'ZROS_LISTEN', 'ZROS_DISCOVERY', 'ZROS_CONFIG', 'ROS_DOMAIN_ID', 'ZENOH_CONFIG')
#: zros's own suite also starts without a developer's search paths and log format.
ALL_SETTINGS = NETWORK_SETTINGS + ('ZROS_INTERFACE_PATH', 'ZROS_NODE_PATH', 'RCUTILS_CONSOLE_OUTPUT_FORMAT',
                                   'RCUTILS_LOGGING_USE_STDOUT', 'ZROS_MAX_MESSAGE_SIZE', 'ZROS_MAX_REQUEST_SIZE', 'ZROS_SHM_POOL_SIZE',
                                   'ZROS_TOPIC_PRIORITY', 'ZROS_CALLBACK_THREAD',
                                   'ROS_SECURITY_ENABLE', 'ROS_SECURITY_KEYSTORE', 'ROS_SECURITY_STRATEGY',
                                   'ROS_SECURITY_ENCLAVE_OVERRIDE')


class DomainLock:
    """Holds one domain id (an flock'ed file) until `close()`; `domain` is the id."""

    def __init__(self) -> None:
        lock_dir = Path(tempfile.gettempdir()) / 'zros-test-domains'
        lock_dir.mkdir(exist_ok=True)
        candidates = list(range(DOMAIN_RANGE[0], DOMAIN_RANGE[1] + 1))
        random.shuffle(candidates)
        for domain in candidates:
            if not hub_port_free(domain):
                continue
            handle: IO = open(lock_dir / f'{domain}.lock', 'w')
            try:
                fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except OSError:
                handle.close()
                continue
            self.domain, self._handle = domain, handle
            return
        raise RuntimeError(f'no free zros test domain in {DOMAIN_RANGE[0]}..{DOMAIN_RANGE[1]}')

    def close(self) -> None:
        self._handle.close()


def isolated_environment(monkeypatch: object, domain: int, scrub: tuple[str, ...] = NETWORK_SETTINGS) -> None:
    """Set the test's environment (pytest's MonkeyPatch): the domain, none of `scrub`,
    unbuffered and uncoloured output from the processes it starts."""
    for name in scrub:
        monkeypatch.delenv(name, raising=False)
    monkeypatch.setenv('ZROS_DOMAIN_ID', str(domain))
    monkeypatch.setenv('RCUTILS_COLORIZED_OUTPUT', '0')
    monkeypatch.setenv('PYTHONUNBUFFERED', '1')


class _EnvironmentEdits:
    """MonkeyPatch's setenv/delenv on os.environ, undone by `undo()` (outside pytest)."""

    def __init__(self) -> None:
        self._saved: dict[str, str | None] = {}

    def setenv(self, name: str, value: str) -> None:
        self._saved.setdefault(name, os.environ.get(name))
        os.environ[name] = value

    def delenv(self, name: str, raising: bool = True) -> None:
        self._saved.setdefault(name, os.environ.get(name))
        os.environ.pop(name, None)

    def undo(self) -> None:
        for name, value in self._saved.items():
            if value is None:
                os.environ.pop(name, None)
            else:
                os.environ[name] = value


@contextmanager
def isolated_domain(scrub: tuple[str, ...] = NETWORK_SETTINGS) -> Iterator[int]:
    """`with isolated_domain() as domain:` this process and the processes it starts use a
    private domain (as the `zros_domain` fixture gives a test); the environment is restored
    and the domain released afterwards. For runs outside pytest's fixtures: a launch test."""
    lock = DomainLock()
    edits = _EnvironmentEdits()
    try:
        isolated_environment(edits, lock.domain, scrub)
        yield lock.domain
    finally:
        edits.undo()
        lock.close()
