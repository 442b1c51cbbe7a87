"""The pytest plugin of zros.testing (registered as the `zros` pytest11 entry point): the
fixtures `zros_domain`, `zros_context`, `zros_node`, `zros_processes` (see zros.testing), and
the collection of launch_testing modules (zros.testing.launch_tests), with `--launch-args`."""
from __future__ import annotations

from pathlib import Path
from typing import Any, Callable, Iterator

import pytest

from zros.testing.domains import NETWORK_SETTINGS, DomainLock, isolated_environment
from zros.testing.processes import ProcessGroup

__all__ = ['zros_domain', 'zros_context', 'zros_node', 'zros_processes', 'pytest_addoption',
           'pytest_pycollect_makemodule']


def pytest_addoption(parser: pytest.Parser) -> None:
    parser.addoption('--launch-args', action='append', nargs='*', default=[], metavar='name:=value',
                     help='launch arguments for the launch tests (modules defining generate_test_description)')


def pytest_pycollect_makemodule(module_path: Path, parent: pytest.Collector) -> pytest.Module | None:
    """A launch test module becomes one item that runs its launch and tests; others are left
    to pytest."""
    from zros.testing.launch_tests import make_launch_test_module
    return make_launch_test_module(module_path, parent)


@pytest.fixture
def zros_domain(monkeypatch: pytest.MonkeyPatch) -> Iterator[int]:
    """A private domain id for this test, exported as ZROS_DOMAIN_ID (for its processes too)."""
    lock = DomainLock()
    isolated_environment(monkeypatch, lock.domain, NETWORK_SETTINGS)
    yield lock.domain
    lock.close()


@pytest.fixture
def zros_context(zros_domain: int) -> Iterator[Any]:
    """zros initialized in the test's domain for this process (`zros.init()`); shut down after."""
    import zros
    context = zros.init([], signal_handler_options=False)   # pytest keeps its own Ctrl-C handling
    yield context
    zros.try_shutdown()   # the test may have shut it down itself


@pytest.fixture
def zros_node(zros_context: Any) -> Iterator[Callable[..., Any]]:
    """`zros_node('name', **Node options)` -> a Node in the test's context, destroyed after."""
    from zros.node import Node
    nodes: list = []

    def make(name: str, **kwargs: Any) -> Any:
        node = Node(name, context=zros_context, **kwargs)
        nodes.append(node)
        return node
    yield make
    for node in reversed(nodes):
        node.destroy_node()


@pytest.fixture
def zros_processes(zros_domain: int, tmp_path: Path) -> Iterator[ProcessGroup]:
    """Processes in the test's domain (`.run(pkg, exe)`, `.launch(file)`, `.command(*argv)`),
    stopped with their process groups after the test; their logs are in tmp_path."""
    group = ProcessGroup(tmp_path)
    yield group
    group.close()
