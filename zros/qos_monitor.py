"""Watches the graph for one node's publishers and subscriptions: incompatible QoS pairs and
endpoints of another type (each reported once, as ROS 2 does), and the matches that the QoS
events of zros.event_handler report.

ROS 2 (DDS) silently matches nothing across an incompatible pair and tells the user in a
warning. Zenoh still connects the two, so zros delivers the messages; the warning says that
too, so a system that will later run on ROS 2 is not surprised.
"""
from __future__ import annotations

import threading
from typing import TYPE_CHECKING, Any

from zros.event_handler import graph_changed, report_incompatible_qos, report_incompatible_type, same_type
from zros.graph import Entity, EntityKind
from zros.qos import QoSProfile, qos_incompatibilities

if TYPE_CHECKING:
    from zros.node import Node

__all__ = ['QoSMonitor']


class QoSMonitor:
    """One graph listener per node, for all its endpoints."""

    def __init__(self, node: 'Node') -> None:
        self._node = node
        self._reported: set[tuple[int, tuple]] = set()
        self._lock = threading.Lock()
        node.context.graph.add_listener(self.check)
        self.check()

    def close(self) -> None:
        try:
            self._node.context.graph.remove_listener(self.check)
        except Exception:  # noqa: BLE001 - the context may already be gone
            pass

    def check(self) -> None:
        try:
            others = self._node.context.graph.entities()
        except Exception:  # noqa: BLE001 - called from Zenoh threads while shutting down
            return
        for endpoint in self._node._own_endpoint_objects():
            mine = endpoint.graph_entity
            for other in others:
                if other.name == mine.name and {mine.kind, other.kind} == {EntityKind.PUBLISHER,
                                                                           EntityKind.SUBSCRIPTION}:
                    if same_type(mine, other):
                        self._compare(endpoint, mine, other)
                    else:
                        report_incompatible_type(endpoint, other)
            graph_changed(endpoint, others)

    def _compare(self, endpoint: Any, mine: Entity, other: Entity) -> None:
        pub, sub = (mine, other) if mine.kind == EntityKind.PUBLISHER else (other, mine)
        found = qos_incompatibilities(QoSProfile.from_token(pub.qos), QoSProfile.from_token(sub.qos))
        if not found:
            return
        key = (mine.entity_id, (other.zid, other.node_id, other.entity_id))
        with self._lock:
            if key in self._reported:
                return
            self._reported.add(key)
        report_incompatible_qos(endpoint, found[-1][0], other)
