"""Service clients: a request is one Zenoh get; its reply completes a Future.

Replies complete the future on Zenoh's thread, so a blocking `call()` works even from inside
a callback of a single-threaded executor (rclpy deadlocks there). Done-callbacks still run on
the node's executor. A call fails with ServiceCallError when the server raises or refuses the
request, when it disappears (Zenoh finalizes the query at once), or after `timeout_sec`.
"""
from __future__ import annotations

import time
from typing import TYPE_CHECKING, Any, Iterator

from zros.entity import NodeEntity
from zros.errors import DecodeError, ServiceCallError
from zros.graph import EntityKind
from zros.message import deserialize, serialize
from zros.qos import QoSProfile
from zros.shm import payload as shm_payload
from zros.task import Future
from zros.wire import AttachmentWriter, max_message_size

if TYPE_CHECKING:
    from zros.node import Node

__all__ = ['Client']

# rclpy's call_async has no timeout; Zenoh needs one. A day is "never" for a request, and a
# server that dies still fails the call at once.
_NO_TIMEOUT = 86_400.0


class Client(NodeEntity):
    """Made by `Node.create_client`."""

    def __init__(self, node: 'Node', srv_type: type, name: str, qos: QoSProfile, callback_group: Any) -> None:
        from zros.keys import service_key
        self.srv_type = srv_type
        self.srv_name = name
        self.qos_profile = qos
        self.callback_group = callback_group
        self._key = service_key(node.context.domain_id, name)
        self._stamp = AttachmentWriter(srv_type).next
        self._max_reply = max_message_size()
        super().__init__(node, EntityKind.CLIENT, name, srv_type, qos)

    @property
    def service_name(self) -> str:
        return self.srv_name

    def _servers(self, entities: list) -> list:
        return [e for e in entities if e.kind == EntityKind.SERVICE and e.name == self.srv_name]

    def service_is_ready(self) -> bool:
        return bool(self._servers(self._node.context.graph.entities()))

    def wait_for_service(self, timeout_sec: float | None = None) -> bool:
        """Wait (on graph changes, not by polling) until a server exists; False on timeout."""
        return self._node.context.graph.wait_for(lambda entities: bool(self._servers(entities)), timeout_sec)

    def _send(self, request: Any, timeout_sec: float | None, handler: Any = None,
              parameters: str = '') -> tuple[float, Any]:
        """Issue the Zenoh get for `request`: (timeout used, reply receiver or None).

        With no handler, Zenoh's default FIFO channel holds the replies for the caller.
        `parameters` go in the selector (`key?parameters`) for servers that read them."""
        import zenoh
        if type(request) is not self.srv_type.Request:
            raise TypeError(f"client of '{self.srv_name}' expects {self.srv_type._TYPE} Request, "
                            f'got {getattr(type(request), "_TYPE", type(request).__name__)}')
        if self._destroyed:
            raise RuntimeError(f"client of '{self.srv_name}' has been destroyed")
        timeout = _NO_TIMEOUT if timeout_sec is None else max(0.001, timeout_sec)
        receiver = self._node.context.session.get(
            f'{self._key}?{parameters}' if parameters else self._key, handler,
            payload=shm_payload(serialize(request)), attachment=self._stamp(),
            timeout=timeout, consolidation=zenoh.ConsolidationMode.NONE)
        return timeout, receiver

    def _outcome(self, reply: Any, started: float, response_type: type | None = None) -> Any:
        """The response in a reply (a `response_type`, by default this service's Response), or
        the ServiceCallError it stands for (returned, not raised)."""
        ok = reply.ok
        if ok is not None:
            payload = ok.payload
            if len(payload) > self._max_reply:
                return ServiceCallError(f"service '{self.srv_name}' sent a reply of {len(payload)} bytes, larger "
                                        f'than the limit of {self._max_reply} bytes (ZROS_MAX_MESSAGE_SIZE)')
            try:
                return deserialize(payload.to_bytes(), response_type or self.srv_type.Response)
            except DecodeError as exc:  # a bad reply fails this call only
                return ServiceCallError(f"service '{self.srv_name}' sent a reply that is not a valid response: {exc}")
        text = reply.err.payload.to_bytes().decode(errors='replace')
        if text == 'Timeout':  # Zenoh's own reply when the query's timeout expires
            return ServiceCallTimeout(f"service '{self.srv_name}' did not answer: timed out after "
                                      f'{time.monotonic() - started:.2f} s')
        return ServiceCallError(f"service '{self.srv_name}' failed: {text}")

    def _no_answer(self, started: float, timeout: float) -> ServiceCallError:
        waited = time.monotonic() - started
        if waited >= timeout * 0.99:
            return ServiceCallTimeout(f"service '{self.srv_name}' did not answer: timed out after {waited:.2f} s")
        return ServiceCallError(f"service '{self.srv_name}' did not answer: the server went away before "
                                f'answering (or none is running) after {waited:.2f} s')

    def call_async(self, request: Any, *, timeout_sec: float | None = None) -> Future:
        """Send `request`; the Future gets the Response, or a ServiceCallError."""
        import zenoh
        future = Future(node=self._node)
        started = time.monotonic()

        def on_reply(reply: Any) -> None:
            if not future.done():
                outcome = self._outcome(reply, started)
                if isinstance(outcome, Exception):
                    future.set_exception(outcome)
                else:
                    future.set_result(outcome)

        # Known before the query is sent: with no server, Zenoh may call on_done before _send returns.
        timeout = _NO_TIMEOUT if timeout_sec is None else max(0.001, timeout_sec)

        def on_done() -> None:
            if not future.done():
                future.set_exception(self._no_answer(started, timeout))

        self._send(request, timeout_sec, zenoh.handlers.Callback(on_reply, on_done))
        return future

    def call(self, request: Any, timeout_sec: float | None = None) -> Any:
        """Blocking call; raises ServiceCallError (ServiceCallTimeout, a TimeoutError, on timeout).

        The reply is read from Zenoh's channel on this thread (no hand-over from a callback
        thread), so it needs no executor and works inside callbacks."""
        return next(self._replies(request, timeout_sec, (self.srv_type.Response,)))

    def _replies(self, request: Any, timeout_sec: float | None, response_types: tuple[type, ...],
                 parameters: str = '') -> Iterator[Any]:
        """Blocking: send `request`, then yield its replies, decoded as `response_types` in
        order (a server may answer one query more than once). Raises ServiceCallError for a
        failed reply, or when the query ends before a reply expected."""
        started = time.monotonic()
        timeout, receiver = self._send(request, timeout_sec, parameters=parameters)
        replies = iter(receiver)
        for response_type in response_types:
            reply = next(replies, None)
            outcome = (self._no_answer(started, timeout) if reply is None
                       else self._outcome(reply, started, response_type))
            if isinstance(outcome, Exception):
                raise outcome
            yield outcome


class ServiceCallTimeout(ServiceCallError, TimeoutError):
    """`Client.call` with a timeout raises this (rclpy raises TimeoutError)."""
