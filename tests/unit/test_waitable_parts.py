"""The pure parts of zros.waitable, callback groups' rclpy-named bracket and type_support's checks."""
from __future__ import annotations

import pytest

from zros.callback_groups import MutuallyExclusiveCallbackGroup, ReentrantCallbackGroup
from zros.waitable import NumberOfEntities, Waitable, WaitSet


def test_entity_counts_add_up():
    total = NumberOfEntities(1, 2, 3, 4, 5, 6)
    total += NumberOfEntities(10, 20, 30, 40, 50, 60)
    assert (total.num_subscriptions, total.num_guard_conditions, total.num_timers, total.num_clients,
            total.num_services, total.num_events) == (11, 22, 33, 44, 55, 66)
    assert total == NumberOfEntities(11, 22, 33, 44, 55, 66)
    assert repr(NumberOfEntities(1)) == '<NumberOfEntities(1, 0, 0, 0, 0, 0)>'


class _Flag:
    """Stands for a zros entity: what the wait set asks is `_has_work()`."""

    def __init__(self, work: bool) -> None:
        self.work = work

    def _has_work(self) -> bool:
        return self.work


class _Due:
    """Stands for a timer: asked through `is_ready()`."""

    def is_ready(self) -> bool:
        return True


def test_a_wait_set_answers_for_what_was_added():
    wait_set = WaitSet()
    idle = wait_set.add_subscription(_Flag(False))
    busy = wait_set.add_subscription(_Flag(True))
    timer = wait_set.add_timer(_Due())
    assert (idle, busy, timer) == (0, 1, 0)
    assert not wait_set.is_ready('subscription', idle)
    assert wait_set.is_ready('subscription', busy)
    assert wait_set.is_ready('timer', timer)
    assert not wait_set.is_ready('guard_condition', None)   # asked before anything was added
    assert not wait_set.is_ready('client', 3)


def test_a_waitable_joins_its_group_and_its_hooks_are_abstract():
    group = ReentrantCallbackGroup()
    waitable = Waitable(group)
    assert group.has_entity(waitable) and not MutuallyExclusiveCallbackGroup().has_entity(waitable)
    with pytest.raises(NotImplementedError):
        waitable.is_ready(WaitSet())
    future = object()
    waitable.add_future(future)
    waitable.remove_future(future)


def test_groups_answer_to_rclpys_bracket_names():
    group = MutuallyExclusiveCallbackGroup()
    assert group.beginning_execution('a') and not group.can_execute('b')
    assert not group.beginning_execution('b')
    group.ending_execution('a')
    assert group.beginning_execution('b')
    reentrant = ReentrantCallbackGroup()
    assert reentrant.beginning_execution('a') and reentrant.beginning_execution('b')
