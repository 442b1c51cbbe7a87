"""What publishers, subscriptions, services and clients have in common: a graph entry that
announces them and a Zenoh handle they own, both released by one idempotent `destroy()`."""
from __future__ import annotations

from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from zros.graph import Entity
    from zros.node import Node

__all__ = ['NodeEntity']


class NodeEntity:
    """Base class; subclasses set `_zenoh` (the declared publisher/subscriber/queryable or None)
    and may extend `_release()` for their own clean-up."""

    _zenoh: Any = None

    def __init__(self, node: 'Node', kind: str, name: str, iface_type: type, qos: Any) -> None:
        self._node = node
        self._entity = node._declare_entity(kind, name, iface_type, qos)
        self._destroyed = False

    @property
    def handle(self) -> 'Entity':
        """The graph record of this entity (what `zros node info` lists)."""
        return self._entity

    def destroy(self) -> None:
        if self._destroyed:
            return
        self._destroyed = True
        self._node._undeclare_entity(self._entity)
        self._release()

    def _release(self) -> None:
        if self._zenoh is not None:
            try:
                self._zenoh.undeclare()
            except Exception:  # noqa: BLE001 - the session may be closing already
                pass
