"""zros.handle: the lifetime token behind rclpy's `x.handle` (pure, no session)."""
from __future__ import annotations

import pytest

from zros.exceptions import InvalidHandle
from zros.handle import Handle


def test_a_live_handle_can_be_held_and_a_destroyed_one_cannot():
    handle = Handle("publisher '/chatter'")
    with handle as held:
        assert held is handle
    released = []
    assert handle.destroy_when_not_in_use(lambda: released.append(True))
    assert released == [True] and not handle.valid
    with pytest.raises(InvalidHandle, match="publisher '/chatter' has been destroyed"):
        with handle:
            pass


def test_destroy_waits_for_the_last_holder():
    handle = Handle('node')
    released = []
    with handle:
        with handle:
            handle.destroy_when_not_in_use(lambda: released.append('now'))
            assert not handle.valid and released == []   # invalid at once, released later
        assert released == []
    assert released == ['now']


def test_a_second_destroy_releases_nothing():
    handle = Handle('timer')
    released = []
    assert handle.destroy_when_not_in_use(lambda: released.append(1))
    assert not handle.destroy_when_not_in_use(lambda: released.append(2))
    assert released == [1]
    assert 'destroyed' in repr(handle)


def test_attributes_can_be_hung_on_a_handle():
    """rclpy code ties lifetimes together by attribute (`node.handle.context_handle = ...`)."""
    handle = Handle('node')
    handle.context_handle = Handle('context')
    assert handle.context_handle.valid
