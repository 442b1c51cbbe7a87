"""How a subscription decides to call its callback: with the message, or with the message and
its MessageInfo (rclpy's rule: whatever one argument binds to takes the message only)."""
from __future__ import annotations

import pytest

from zros.subscription import Subscription, _callback_type

MessageOnly = Subscription.CallbackType.MessageOnly
WithMessageInfo = Subscription.CallbackType.WithMessageInfo


def _with_default(msg, info=None):
    return msg


class _Listener:
    def on_msg(self, msg, info):
        return msg


@pytest.mark.parametrize('callback, expected', [
    (lambda msg: None, MessageOnly),
    (lambda *args: None, MessageOnly),
    (_with_default, MessageOnly),
    (lambda msg, info: None, WithMessageInfo),
    (_Listener().on_msg, WithMessageInfo),
    (print, MessageOnly),
])
def test_the_callback_type_follows_what_binds(callback, expected):
    assert _callback_type(callback) is expected


def test_a_callback_that_takes_three_arguments_is_refused():
    with pytest.raises(RuntimeError, match='must take the message'):
        _callback_type(lambda msg, info, extra: None)
