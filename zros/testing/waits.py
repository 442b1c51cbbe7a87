"""Waiting in tests: for a condition, a message, a service answer, a node or a topic in the
graph. Every wait has a timeout and fails with `WaitTimeout` (an AssertionError, so pytest
reports it as a test failure) saying what it waited for."""
from __future__ import annotations

import time
from typing import Any, Callable

__all__ = ['WaitTimeout', 'wait_until', 'spin_until', 'wait_for_message', 'call_service', 'wait_for_node',
           'wait_for_topic']


class WaitTimeout(AssertionError):
    """A wait ran out of time."""


def _text(message: str | Callable[[], str]) -> str:
    return message() if callable(message) else message


def wait_until(predicate: Callable[[], Any], timeout: float = 5.0, *, interval: float = 0.02,
               message: str | Callable[[], str] = 'condition') -> Any:
    """Poll `predicate` until it returns something truthy (returned), or raise WaitTimeout."""
    deadline = time.monotonic() + timeout
    while True:
        value = predicate()
        if value:
            return value
        if time.monotonic() >= deadline:
            raise WaitTimeout(f'timed out after {timeout:g} s waiting for {_text(message)}')
        time.sleep(interval)


def spin_until(node_or_executor: Any, predicate: Callable[[], Any], timeout: float = 5.0, *,
               message: str | Callable[[], str] = 'condition') -> Any:
    """Run callbacks (of a node, on an executor of its own, or of an executor) until
    `predicate()` holds (its value is returned), or raise WaitTimeout."""
    from zros.executors import SingleThreadedExecutor
    if hasattr(node_or_executor, 'spin_once'):
        executor, own = node_or_executor, None
    else:
        own = SingleThreadedExecutor(context=node_or_executor.context)
        own.add_node(node_or_executor)
        executor = own
    deadline = time.monotonic() + timeout
    try:
        while True:
            value = predicate()
            if value:
                return value
            remaining = deadline - time.monotonic()
            if remaining <= 0:
                raise WaitTimeout(f'timed out after {timeout:g} s waiting for {_text(message)}')
            executor.spin_once(timeout_sec=min(0.05, remaining))
    finally:
        if own is not None:
            own.remove_node(node_or_executor)
            own.shutdown()


def wait_for_message(node: Any, msg_type: type, topic: str, *, timeout: float = 5.0, qos_profile: Any = 10) -> Any:
    """The first message on `topic` after the call (received through a temporary subscription
    of `node`)."""
    received: list = []
    subscription = node.create_subscription(msg_type, topic, received.append, qos_profile)
    try:
        spin_until(node, lambda: received, timeout, message=f"a message on '{topic}'")
    finally:
        node.destroy_subscription(subscription)
    return received[0]


def call_service(node: Any, srv_type: type, name: str, request: Any, *, timeout: float = 5.0) -> Any:
    """Wait for the service to appear, call it and return the response."""
    client = node.create_client(srv_type, name)
    try:
        if not client.wait_for_service(timeout_sec=timeout):
            raise WaitTimeout(f"timed out after {timeout:g} s waiting for the service '{name}'")
        response = client.call(request, timeout_sec=timeout)
        if response is None:
            raise WaitTimeout(f"timed out after {timeout:g} s waiting for the service '{name}' to answer")
        return response
    finally:
        node.destroy_client(client)


def wait_for_node(node: Any, name: str, *, timeout: float = 5.0) -> None:
    """Until the graph shows the node `name` (fully qualified, e.g. '/talker')."""
    if not node.wait_for_node(name, timeout):
        raise WaitTimeout(f"timed out after {timeout:g} s waiting for the node '{name}'")


def wait_for_topic(node: Any, topic: str, *, publishers: int = 1, subscribers: int = 0,
                   timeout: float = 5.0) -> None:
    """Until `topic` has at least so many publishers and subscribers in the graph."""
    wait_until(lambda: node.count_publishers(topic) >= publishers and node.count_subscribers(topic) >= subscribers,
               timeout, message=f"'{topic}' with {publishers} publisher(s) and {subscribers} subscriber(s)")
