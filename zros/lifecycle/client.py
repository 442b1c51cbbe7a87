"""LifecycleClient: drive another node's lifecycle through its services.

What `ros2 lifecycle`, Nav2's lifecycle manager and BasicNavigator do by hand, in one place:
wait for the node's services, read its state, request a transition. Calls wait on the reply's
future in short slices, so Ctrl-C interrupts them and they work from any thread, callbacks
included.
"""
from __future__ import annotations

import time
from typing import Any

from zros.errors import ServiceCallError
from zros.lifecycle.state_machine import LifecycleState, TransitionDescription

__all__ = ['LifecycleClient']


class LifecycleClient:
    """Clients for `<target>/get_state`, `change_state` and `get_available_transitions`, made on
    `node`. `target` is a node name, absolute or relative to `node`'s namespace."""

    def __init__(self, node: Any, target: str) -> None:
        from interfaces.lifecycle_msgs.srv import ChangeState, GetAvailableTransitions, GetState
        self.node = node
        self.target = target.rstrip('/')
        self._get_state = node.create_client(GetState, f'{self.target}/get_state')
        self._change_state = node.create_client(ChangeState, f'{self.target}/change_state')
        self._transitions = node.create_client(GetAvailableTransitions, f'{self.target}/get_available_transitions')

    @property
    def clients(self) -> tuple[Any, ...]:
        return (self._get_state, self._change_state, self._transitions)

    def wait_for_services(self, timeout_sec: float | None = None) -> bool:
        """Whether the node's lifecycle services exist (waiting up to `timeout_sec`)."""
        deadline = None if timeout_sec is None else time.monotonic() + timeout_sec
        for client in self.clients:
            remaining = None if deadline is None else max(0.0, deadline - time.monotonic())
            if not client.wait_for_service(timeout_sec=remaining):
                return False
        return True

    def get_state(self, timeout_sec: float | None = 2.0) -> LifecycleState:
        """The node's current state; ServiceCallError when it does not answer in time."""
        from interfaces.lifecycle_msgs.srv import GetState
        state = _call(self._get_state, GetState.Request(), timeout_sec).current_state
        return LifecycleState(state.label, state.id)

    def change_state(self, transition: int | str, timeout_sec: float | None = None) -> bool:
        """Request a transition by id (lifecycle_msgs/Transition constants) or label; whether
        the node reports success. `timeout_sec=None` waits as long as the callback runs."""
        from interfaces.lifecycle_msgs.srv import ChangeState
        request = ChangeState.Request()
        if isinstance(transition, str):
            request.transition.label = transition
        else:
            request.transition.id = int(transition)
        return bool(_call(self._change_state, request, timeout_sec).success)

    def available_transitions(self, timeout_sec: float | None = 2.0) -> list[TransitionDescription]:
        from interfaces.lifecycle_msgs.srv import GetAvailableTransitions
        response = _call(self._transitions, GetAvailableTransitions.Request(), timeout_sec)
        return [TransitionDescription(t.transition.id, t.transition.label,
                                      LifecycleState(t.start_state.label, t.start_state.id),
                                      LifecycleState(t.goal_state.label, t.goal_state.id))
                for t in response.available_transitions]

    def destroy(self) -> None:
        for client in self.clients:
            self.node.destroy_client(client)


def _call(client: Any, request: Any, timeout_sec: float | None) -> Any:
    """The response; ServiceCallError on failure, on shutdown, or (a second after the query's
    own timeout, should its completion never arrive) on timeout."""
    future = client.call_async(request, timeout_sec=timeout_sec)
    deadline = None if timeout_sec is None else time.monotonic() + timeout_sec + 1.0
    while not future.wait(0.1):
        if not client._node.context.ok():
            raise ServiceCallError(f"service '{client.srv_name}': zros is shutting down")
        if deadline is not None and time.monotonic() > deadline:
            raise ServiceCallError(f"service '{client.srv_name}' did not answer within {timeout_sec:g} s")
    return future.result()
