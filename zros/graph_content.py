"""What a graph view shows: ros2's hidden-name rule and rqt_graph's node/topic content.

The CLI (`zros node list`, `zros graph`, ...) and the browser's rqt pages filter the same
graph records (zros.graph.Entity) the same way, so the rule lives here, below both of them,
as plain functions on those records.
"""
from __future__ import annotations

from typing import Iterable

from zros.graph import Entity, EntityKind

__all__ = ['DEBUG_TOPICS', 'is_hidden', 'graph_content']

#: The topics rqt_graph leaves out unless debug is asked for.
DEBUG_TOPICS = ('/rosout', '/parameter_events')


def is_hidden(name: str) -> bool:
    """ros2's rule: any token of the name starting with '_' hides it."""
    return any(part.startswith('_') for part in name.split('/') if part)


def graph_content(entities: Iterable[Entity], *, include_hidden: bool = False, include_debug: bool = False) -> dict:
    """The node/topic graph as rqt_graph draws it: nodes (ellipses), topics (boxes) and an edge
    from each publishing node to its topic and from the topic to each subscribing node.

    Args:
        entities: the graph's records (zros.graph.fetch_entities, Graph.entities()).
        include_hidden: keep names with a part starting with '_' (is_hidden).
        include_debug: keep DEBUG_TOPICS.

    Returns:
        {'nodes': [fqn...], 'topics': {name: [types]}, 'edges': [(from, to)]}, all sorted, edge
        ends written 'n:<node fqn>' or 't:<topic>'.
    """
    entities = list(entities)
    nodes = sorted({e.node_fqn for e in entities if e.kind == EntityKind.NODE
                    and (include_hidden or not is_hidden(e.node_fqn))})
    shown = set(nodes)
    topics: dict[str, set[str]] = {}
    edges = set()
    for e in entities:
        if e.kind not in (EntityKind.PUBLISHER, EntityKind.SUBSCRIPTION) or e.node_fqn not in shown:
            continue
        if (not include_hidden and is_hidden(e.name)) or (not include_debug and e.name in DEBUG_TOPICS):
            continue
        topics.setdefault(e.name, set()).add(e.type)
        if e.kind == EntityKind.PUBLISHER:
            edges.add(('n:' + e.node_fqn, 't:' + e.name))
        else:
            edges.add(('t:' + e.name, 'n:' + e.node_fqn))
    return {'nodes': nodes, 'topics': {k: sorted(v) for k, v in sorted(topics.items())}, 'edges': sorted(edges)}
