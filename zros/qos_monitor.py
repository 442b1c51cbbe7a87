"""Reports incompatible QoS pairs the way ROS 2 does, once per pair, from graph changes.

ROS 2 (DDS) silently matches nothing across such a pair and tells the user in a warning.
Zenoh still connects the two, so zros delivers the messages; the warning says that too, so a
system that will later run on ROS 2 is not surprised.
"""
from __future__ import annotations

import threading
from typing import TYPE_CHECKING

from zros.graph import Entity, EntityKind
from zros.qos import QoSCompatibility, QoSProfile, qos_check_compatible

if TYPE_CHECKING:
    from zros.node import Node

__all__ = ['QoSMonitor']


def _policy(reason: str) -> str:
    return 'RELIABILITY' if 'eliab' in reason or 'effort' in reason.lower() else 'DURABILITY'


class QoSMonitor:
    """Watches the graph for endpoints that do not match this node's publishers/subscriptions."""

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
        for mine in self._node._own_endpoints():
            for other in others:
                if other.name != mine.name or other.kind == mine.kind:
                    continue
                if {mine.kind, other.kind} != {EntityKind.PUBLISHER, EntityKind.SUBSCRIPTION}:
                    continue
                self._compare(mine, other)

    def _compare(self, mine: Entity, other: Entity) -> None:
        pub, sub = (mine, other) if mine.kind == EntityKind.PUBLISHER else (other, mine)
        verdict, reason = qos_check_compatible(QoSProfile.from_token(pub.qos), QoSProfile.from_token(sub.qos))
        if verdict != QoSCompatibility.ERROR:
            return
        key = (mine.entity_id, (other.zid, other.node_id, other.entity_id))
        with self._lock:
            if key in self._reported:
                return
            self._reported.add(key)
        if mine.kind == EntityKind.SUBSCRIPTION:
            text = (f"New publisher discovered on topic '{mine.name}', offering incompatible QoS. "
                    f'Last incompatible policy: {_policy(reason)} (publisher {other.node_fqn}; '
                    'ROS 2 would receive nothing from it, zros still delivers)')
        else:
            text = (f"New subscription discovered on topic '{mine.name}', requesting incompatible QoS. "
                    f'Last incompatible policy: {_policy(reason)} (subscription {other.node_fqn}; '
                    'ROS 2 would deliver nothing to it, zros still does)')
        self._node.get_logger().warn(text)
