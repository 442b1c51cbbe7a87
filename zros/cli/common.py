"""What several CLI verbs share: a short-lived context and node, and graph reads."""
from __future__ import annotations

import os
import sys
import time
from typing import Any

from zros.context import Context
from zros.graph import Entity, fetch_entities

__all__ = ['cli_context', 'cli_node', 'graph_entities', 'wait_for_graph', 'absolute_name',
           'absolute_node_name']

CLI_NODE_PREFIX = '_zros_cli_'


# How long a command waits for the router of a client-mode configuration.
_CLIENT_CONNECT_WAIT_S = 2.0


def cli_context(*, graph_only: bool = False) -> Context:
    """A context for one CLI command (no node signal handlers: zros.cli.main's own end it).

    `graph_only`: the command only reads the graph, so its session links to the hub or router
    alone, not to every process (with 50 nodes up that is 1 link instead of 51, and the
    difference between 40 ms and a second)."""
    return Context().init([], install_signal_handlers=False, mesh=not graph_only,
                          connect_wait=_CLIENT_CONNECT_WAIT_S)


def cli_node(context: Context) -> Any:
    """A hidden node (leading '_', as ros2cli's) for verbs that subscribe or publish."""
    from zros.node import Node
    return Node(f'{CLI_NODE_PREFIX}{os.getpid()}', context=context, enable_rosout=False,
                use_global_arguments=False)


_warned_partial = False


def graph_entities(context: Context, timeout: float = 1.0) -> list[Entity]:
    """The graph, read within `timeout`; a read cut short says so once on stderr (the command
    still answers with what it has, rather than hang)."""
    global _warned_partial
    entities = fetch_entities(context.session, context.domain_id, timeout, is_hub=context.is_hub,
                              hub_wait=context.hub_wait)
    if not entities.complete and not _warned_partial:
        _warned_partial = True
        print(f'zros: the graph read did not complete within {timeout:g} s; the answer may be partial',
              file=sys.stderr, flush=True)
    return entities


def wait_for_graph(context: Context, predicate, timeout: float) -> list[Entity] | None:
    """Re-read the graph until `predicate(entities)` holds; the entities, or None on timeout."""
    deadline = time.monotonic() + timeout
    while True:
        entities = graph_entities(context)
        if predicate(entities):
            return entities
        if time.monotonic() >= deadline:
            return None
        time.sleep(0.05)


def absolute_name(name: str, kind: str = 'topic name') -> str:
    """A topic, service or action name as typed on the command line, made absolute and
    validated (a CLI has no namespace of its own: 'chatter' means '/chatter')."""
    from zros.names import expand_topic_name
    return expand_topic_name(name, 'zros', '/', kind=kind)


def absolute_node_name(name: str) -> str:
    """'talker' and '/talker' both name the node /talker."""
    return name if name.startswith('/') else '/' + name
