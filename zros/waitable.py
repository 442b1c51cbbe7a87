"""User-defined waitables (rclpy.waitable): something a node adds with `add_waitable` that the
executor asks, each time it looks for work, whether it has any, and then runs.

rclpy's executor hands each waitable an rcl wait set to add its C entities to. zros has no
wait set (its entities queue their own work, see zros.executors), so the `wait_set` a zros
waitable gets is a `WaitSet` of zros objects: `add_subscription(sub)` and the like return an
index and `is_ready(kind, index)` tells whether that entity has work waiting, and a waitable
that tracks readiness its own way may ignore it. The executor polls its nodes' waitables
whenever it wakes, and at least every `POLL_PERIOD` while one of them is added, so a waitable
made ready from another thread runs within that period.

The contract, as rclpy's: the executor calls `add_to_wait_set(wait_set)`, then
`is_ready(wait_set)`, both inside `with waitable:`; when ready (and its callback group is free)
it calls `take_data()` and runs `execute(taken_data)` (a coroutine, as a task that holds the
group until it ends) on the executor's thread. A waitable is not polled again while a run of it
is pending.
"""
from __future__ import annotations

from typing import Any

__all__ = ['NumberOfEntities', 'Waitable', 'WaitSet', 'POLL_PERIOD', 'waitable_lists_changed',
           'waitable_lists_version']

#: Longest time [s] a ready waitable waits for the executor to poll it.
POLL_PERIOD = 0.02

# Bumped whenever a node gains or loses a waitable, so executors rebuild their list only then.
_waitable_lists_version = 0


def waitable_lists_changed() -> None:
    """Note that some node gained or lost a waitable."""
    global _waitable_lists_version
    _waitable_lists_version += 1


def waitable_lists_version() -> int:
    """The counter `waitable_lists_changed` bumps."""
    return _waitable_lists_version


class NumberOfEntities:
    """How many entities of each kind a waitable waits on (rclpy sizes its wait set with it;
    zros only keeps it for code that adds them up)."""

    __slots__ = ('num_subscriptions', 'num_guard_conditions', 'num_timers', 'num_clients', 'num_services',
                 'num_events')

    def __init__(self, num_subs: int = 0, num_gcs: int = 0, num_timers: int = 0, num_clients: int = 0,
                 num_services: int = 0, num_events: int = 0) -> None:
        counts = (num_subs, num_gcs, num_timers, num_clients, num_services, num_events)
        for name, count in zip(self.__slots__, counts):   # rclpy's positional order
            setattr(self, name, count)

    def __add__(self, other: 'NumberOfEntities') -> 'NumberOfEntities':
        return NumberOfEntities(*(getattr(self, name) + getattr(other, name) for name in self.__slots__))

    def __eq__(self, other: object) -> bool:
        return isinstance(other, NumberOfEntities) and all(
            getattr(self, name) == getattr(other, name) for name in self.__slots__)

    def __repr__(self) -> str:
        counts = ', '.join(str(getattr(self, name)) for name in self.__slots__)
        return f'<NumberOfEntities({counts})>'


class WaitSet:
    """What a zros executor passes to `add_to_wait_set` and `is_ready`: the zros entities a
    waitable waits on, by kind, each answered by whether it has work waiting."""

    _KINDS = ('subscription', 'guard_condition', 'timer', 'client', 'service', 'event')

    def __init__(self) -> None:
        self._entities: dict[str, list[Any]] = {kind: [] for kind in self._KINDS}

    def _add(self, kind: str, entity: Any) -> int:
        self._entities[kind].append(entity)
        return len(self._entities[kind]) - 1

    def add_subscription(self, subscription: Any) -> int:
        """Wait on a zros Subscription; returns its index for `is_ready('subscription', i)`."""
        return self._add('subscription', subscription)

    def add_guard_condition(self, guard_condition: Any) -> int:
        """Wait on a zros GuardCondition; returns its index."""
        return self._add('guard_condition', guard_condition)

    def add_timer(self, timer: Any) -> int:
        """Wait on a zros Timer; returns its index."""
        return self._add('timer', timer)

    def add_client(self, client: Any) -> int:
        """Wait on a zros Client; returns its index."""
        return self._add('client', client)

    def add_service(self, service: Any) -> int:
        """Wait on a zros Service; returns its index."""
        return self._add('service', service)

    def is_ready(self, kind: str, index: int | None) -> bool:
        """Whether the entity added as `kind` at `index` has work waiting (False for None, as a
        waitable asks before it added anything)."""
        entities = self._entities.get(kind, [])
        if index is None or not 0 <= index < len(entities):
            return False
        entity = entities[index]
        if hasattr(entity, '_has_work'):
            return bool(entity._has_work())
        return bool(getattr(entity, 'is_ready', lambda: False)())


class Waitable:
    """Base class of user-defined waitables (rclpy.waitable.Waitable): subclass it, implement
    the five methods below, and give an instance to `Node.add_waitable`.

    Args:
        callback_group: the group `execute` runs in.
    """

    def __init__(self, callback_group: Any) -> None:
        self.callback_group = callback_group
        add_entity = getattr(callback_group, 'add_entity', None)
        if add_entity is not None:
            add_entity(self)
        self._executor_event = False   # a run is queued on the executor: do not poll again
        self._futures: list[Any] = []

    def __enter__(self) -> None:
        """Mark what the waitable wraps as in use while the executor asks it (override)."""

    def __exit__(self, *exc: object) -> None:
        """Mark it free again (override)."""

    def add_future(self, future: Any) -> None:
        """Keep `future` with the waitable (rclpy's bookkeeping for futures it completes)."""
        self._futures.append(future)

    def remove_future(self, future: Any) -> None:
        """Forget a future given to `add_future`."""
        self._futures.remove(future)

    def is_ready(self, wait_set: WaitSet) -> bool:
        """Whether the waitable has work now."""
        raise NotImplementedError('Must be implemented by subclass')

    def take_data(self) -> Any:
        """Take what `execute` works on, so that the waitable is not ready again for it."""
        raise NotImplementedError('Must be implemented by subclass')

    async def execute(self, taken_data: Any) -> None:
        """Do the work, on the executor, with what `take_data` returned."""
        raise NotImplementedError('Must be implemented by subclass')

    def get_num_entities(self) -> NumberOfEntities:
        """How many entities of each kind the waitable adds to the wait set."""
        raise NotImplementedError('Must be implemented by subclass')

    def add_to_wait_set(self, wait_set: WaitSet) -> None:
        """Add the entities the waitable waits on to `wait_set`."""
        raise NotImplementedError('Must be implemented by subclass')
