"""A command that only reads the graph (`zros node list`, `topic list`, ...) opens one client link
to whatever holds the hub port, the loopback hub or a `zros router`, and does not wait for that
side's declarations (issue 36: a laptop's `zros node list` right after the link returns)."""
from __future__ import annotations

import subprocess
import sys
import time

from zros.cli.common import cli_context, graph_entities
from zros.config import HUB_BASE_PORT
from zros.graph import EntityKind

from conftest import REPO

# What `zros node list` must never load: the CLI starts in ~0.1 s only without them.
HEAVY = ('numpy', 'scipy', 'pymunk', 'yaml', 'viser', 'interfaces', 'zros.sim', 'zros.navigation', 'zros.node')


def _node_names(entities) -> set[str]:
    return {e.node_fqn for e in entities if e.kind == EntityKind.NODE}


def test_a_graph_read_through_a_zros_router_is_one_link_and_complete(domain, spawn, wait_for):
    spawn(sys.executable, '-m', 'zros', 'router', '--listen', f'tcp/127.0.0.1:{HUB_BASE_PORT + domain}',
          name='router').wait_for_output('listening on', timeout=20)
    spawn.node('demo_nodes', 'talker').wait_for_output('Publishing', timeout=20)
    started = time.monotonic()
    with cli_context(graph_only=True) as ctx:
        # Zenoh gives a router 0.5 s to send its declarations on every open; a peer session
        # (probe the port, then join the router as a meshed peer) paid that twice
        assert time.monotonic() - started < 0.9
        wait_for(lambda: '/talker' in _node_names(graph_entities(ctx)), 10, message='/talker in the graph')
        entities = graph_entities(ctx)
        assert entities.complete                          # the router answered the graph query
        assert len(list(ctx.session.info.routers_zid())) == 1
        assert list(ctx.session.info.peers_zid()) == []   # no link to the talker itself


def test_a_graph_read_of_the_loopback_hub_needs_no_mesh(domain, spawn, wait_for):
    spawn.node('demo_nodes', 'talker').wait_for_output('Publishing', timeout=20)   # the hub
    spawn.node('demo_nodes', 'listener')
    with cli_context(graph_only=True) as ctx:
        assert not ctx.is_hub
        wait_for(lambda: {'/talker', '/listener'} <= _node_names(graph_entities(ctx)), 10,
                 message='both nodes in the graph')
        assert len(list(ctx.session.info.peers_zid())) <= 1   # the hub, and no one else


def test_node_list_imports_no_numpy_and_no_messages(domain, spawn):
    spawn.node('demo_nodes', 'talker').wait_for_output('Publishing', timeout=20)
    code = ('import sys; from zros.cli.main import main; code = main(["node", "list"]); '
            f'print(sorted(m for m in {HEAVY!r} if m in sys.modules), code)')
    started = time.monotonic()
    result = subprocess.run([sys.executable, '-c', code], capture_output=True, text=True, timeout=30, cwd=REPO)
    assert result.stdout.splitlines() == ['/talker', '[] 0'], result
    assert time.monotonic() - started < 10                # bounded even on a loaded machine
