"""The unit tier's guard: a test under tests/unit runs in this process, alone.

tests/unit is what a developer runs on every save (`pytest tests/unit`, under a minute), so a
test here must not start a process or open a Zenoh session: one that does is slow, needs free
ports and can leave children behind, and it belongs under tests/integration. The guard makes
that a failure rather than a slow drift: `zenoh.open` and `subprocess.Popen` refuse, and so do
the fixtures that start processes or sessions. A test whose unit *is* a session opts out with
`@pytest.mark.session`. The shared fixtures still come from tests/conftest.py.
"""
from __future__ import annotations

import subprocess

import pytest
import zenoh

#: fixtures of tests/conftest.py and zros.testing that start processes or open sessions.
PROCESS_AND_SESSION_FIXTURES = frozenset({
    'spawn', 'module_spawn', 'zros_cli', 'fresh_venv', 'make_context', 'context', 'raw_session', 'probe',
    'zros_context', 'zros_node', 'zros_processes',
})


def _refusal(nodeid: str, what: str) -> str:
    return (f'{nodeid}: a unit test {what}; move it to tests/integration, or mark it '
            f'@pytest.mark.session if its unit is a session')


@pytest.fixture(autouse=True)
def _no_processes_or_sessions(request: pytest.FixtureRequest, monkeypatch: pytest.MonkeyPatch) -> None:
    """Fail an unmarked unit test that opens a Zenoh session or spawns a subprocess."""
    if request.node.get_closest_marker('session'):
        return
    nodeid = request.node.nodeid
    used = sorted(PROCESS_AND_SESSION_FIXTURES.intersection(request.fixturenames))
    if used:
        pytest.fail(_refusal(nodeid, f'uses the fixture {", ".join(used)}'), pytrace=False)

    def refuse_session(*args: object, **kwargs: object) -> None:
        pytest.fail(_refusal(nodeid, 'opened a Zenoh session'), pytrace=False)

    def refuse_process(self: subprocess.Popen, args: object, *rest: object, **kwargs: object) -> None:
        pytest.fail(_refusal(nodeid, f'started the process {args!r}'), pytrace=False)

    monkeypatch.setattr(zenoh, 'open', refuse_session)
    monkeypatch.setattr(subprocess.Popen, '__init__', refuse_process)
