"""What publishers, subscriptions, services and clients have in common: a graph entry that
announces them and a Zenoh handle they own, both released by one idempotent `destroy()`, and
the opaque `handle` (zros.handle) that rclpy code holds them by."""
from __future__ import annotations

from typing import TYPE_CHECKING, Any

from zros.handle import Handle, HandleOwner

if TYPE_CHECKING:
    from zros.graph import Entity
    from zros.node import Node

__all__ = ['NodeEntity', 'QueuedEntity']


class NodeEntity(HandleOwner):
    """Base class; subclasses set `_zenoh` (the declared publisher/subscriber/queryable or None)
    and may extend `_release()` for their own clean-up."""

    _zenoh: Any = None

    def __init__(self, node: 'Node', kind: str, name: str, iface_type: type, qos: Any) -> None:
        self._node = node
        self._entity = node._declare_entity(kind, name, iface_type, qos)
        self._destroyed = False
        self._handle = Handle(f"{kind} '{name}'")

    @property
    def graph_entity(self) -> 'Entity':
        """The graph record of this entity (what `zros node info` lists)."""
        return self._entity

    def destroy(self) -> None:
        """Leave the graph and release the Zenoh declaration (once no `with handle:` holds it);
        calling it again does nothing."""
        if self._destroyed:
            return
        self._destroyed = True
        self._handle.destroy_when_not_in_use(self._teardown)

    def _teardown(self) -> None:
        self._node._undeclare_entity(self._entity)
        self._release()

    def _release(self) -> None:
        if self._zenoh is not None:
            self._node.context._undeclare(self._zenoh)


class QueuedEntity(NodeEntity):
    """An entity whose work (samples, requests) arrives on Zenoh's thread into `_queue` and is
    run by the executor. It sits in the executor's queue at most once while it has work, so a
    burst costs Zenoh's thread an append, not an executor wake-up per item: after appending,
    Zenoh's thread calls `_schedule()` unless `_scheduled` is set."""

    _queue: Any
    _scheduled = False

    def _schedule(self) -> None:
        self._scheduled = True
        executor = self._node._executor
        if executor is not None:
            executor._enqueue(self)

    def _rearm(self) -> None:
        """Executor thread, after taking work: stay queued while more is waiting."""
        if self._queue:
            self._schedule()
        else:
            self._scheduled = False
            if self._queue and not self._scheduled:  # something arrived between the two lines above
                self._schedule()

    def _has_work(self) -> bool:
        return bool(self._queue)
