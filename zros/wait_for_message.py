"""Block until one message arrives on a topic (rclpy.wait_for_message), for scripts and tests
that want a single sample without writing a callback."""
from __future__ import annotations

import time
from typing import TYPE_CHECKING, Any, TypeVar

from zros.executors import SingleThreadedExecutor
from zros.qos import QoSProfile
from zros.task import Future

if TYPE_CHECKING:
    from zros.node import Node

__all__ = ['wait_for_message']

MsgT = TypeVar('MsgT')

# How often a wait on a node spun elsewhere checks that the context is still up [s].
_SLICE_S = 0.1


def wait_for_message(msg_type: type[MsgT], node: 'Node', topic: str, *,
                     qos_profile: QoSProfile | int = 1,
                     time_to_wait: float = -1) -> tuple[bool, MsgT | None]:
    """Subscribe to `topic` through `node`, wait for the next message, then unsubscribe.

    The subscription's callback runs on the node's executor if another thread spins the
    node; otherwise this call spins the node itself on a private executor until the message
    (or the timeout, or shutdown) comes.

    :param msg_type: The message class.
    :param node: The node to subscribe through.
    :param topic: The topic name.
    :param qos_profile: The subscription's QoSProfile, or a history depth.
    :param time_to_wait: How long to wait [s]; negative waits for ever.
    :return: ``(True, msg)``, or ``(False, None)`` on timeout or when the context shuts down.
    """
    arrived: Future[Any] = Future()

    def keep_first(msg: Any) -> None:
        if not arrived.done():
            arrived.set_result(msg)

    timeout = None if time_to_wait is None or time_to_wait < 0 else time_to_wait
    subscription = node.create_subscription(msg_type, topic, keep_first, qos_profile)
    try:
        if node.executor is not None:
            # Another thread spins the node (and rejects a second spin): just wait, checking
            # now and then that the context is still up.
            deadline = None if timeout is None else time.monotonic() + timeout
            while node.context.ok() and not arrived.done():
                left = _SLICE_S if deadline is None else min(_SLICE_S, deadline - time.monotonic())
                if left <= 0:
                    break
                arrived.wait(left)
        else:
            executor = SingleThreadedExecutor(context=node.context)
            executor.add_node(node)
            try:
                executor.spin_until_future_complete(arrived, timeout_sec=timeout)
            finally:
                executor.remove_node(node)
                executor.shutdown()
    finally:
        node.destroy_subscription(subscription)
    if not arrived.done():
        return False, None
    return True, arrived.result()
