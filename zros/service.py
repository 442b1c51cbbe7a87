"""Service servers: Zenoh queryables whose requests are answered on the executor.

A query arrives on Zenoh's thread and waits, unread, in the service's queue; the executor decodes it,
runs the user's callback and replies. Whatever goes wrong is answered, never left hanging: a
request of the wrong type, larger than the limit (zros.wire.max_request_size, refused before it
is decoded), or that does not decode strictly as the request type gets a Zenoh error reply and
is counted in `rejected`, and never reaches the callback; a callback that raises gets an error
reply too. The text of an error reply reaches the client's future; the server logs it and keeps
serving.
"""
from __future__ import annotations

import inspect
from collections import deque
from typing import TYPE_CHECKING, Any, Callable, Generic

from zros.entity import QueuedEntity
from zros.errors import DecodeError
from zros.graph import EntityKind
from zros.message import Srv, SrvRequestT, SrvResponseT, deserialize, serialize
from zros.qos import QoSProfile
from zros.service_introspection import REQUEST_RECEIVED, RESPONSE_SENT, Introspectable, call_origin
from zros.wire import describe_type, foreign_protocol, max_request_size, mismatch_reason, read_header, type_tail

if TYPE_CHECKING:
    from zros.node import Node

__all__ = ['Service', 'DeferredResponse']

# Requests waiting for the executor beyond this are refused with an error reply, so an
# overloaded server fails calls fast instead of letting them time out silently.
_MAX_PENDING = 10_000


class DeferredResponse:
    """Returned by a service callback that will answer later (an action's get-result waits for
    the goal to finish). `resolve(response)` replies and finalizes the query, from any thread;
    `fail(text)` replies with an error."""

    def __init__(self) -> None:
        self._query = None
        self._early: tuple[str, Any] | None = None

    def _bind(self, query: Any) -> None:
        self._query = query
        if self._early is not None:
            kind, value = self._early
            self._finish(kind, value)

    def resolve(self, response: Any) -> None:
        """Send `response` as the answer to the deferred request.

        :param response: An instance of the service's Response type.
        """
        self._finish('ok', response)

    def fail(self, text: str) -> None:
        """Answer the deferred request with an error; the caller's call fails with this text.

        :param text: The error message the client sees in its ServiceCallError.
        """
        self._finish('err', text)

    def _finish(self, kind: str, value: Any) -> None:
        query = self._query
        if query is None:
            self._early = (kind, value)  # answered before the service handed the query over
            return
        self._query = None
        try:
            if kind == 'ok':
                query.reply(query.key_expr, serialize(value))
            else:
                query.reply_err(str(value).encode())
        finally:
            query.drop()


class Service(Introspectable, QueuedEntity, Generic[SrvRequestT, SrvResponseT]):
    """Answers one service; made by `Node.create_service`.

    It owns a Zenoh queryable on the service's key; requests wait in a queue and the callback
    answers them on the node's executor. Generic in the service type.
    """

    #: Called with (query, response) after a response has gone out; a DeferredResponse it returns
    #: answers the same query once more, later (an action's send-goal that also brings the result).
    _follow_up: Callable[[Any, Any], DeferredResponse | None] | None = None

    def __init__(self, node: 'Node', srv_type: type[Srv[SrvRequestT, SrvResponseT]], name: str,
                 callback: Callable[[SrvRequestT, SrvResponseT], Any],
                 qos: QoSProfile, callback_group: Any, *, warn_if_shared: bool = True) -> None:
        from zros.keys import service_key
        self._node = node
        self.srv_type: Any = srv_type   # a class built at run time: its _TYPE is not declared
        self.srv_name = name
        self.callback: Callable[[Any, Any], Any] = callback
        self.qos_profile = qos
        self.callback_group = callback_group
        self._tail = type_tail(srv_type)
        #: Requests larger than this many bytes are refused unread (ZROS_MAX_REQUEST_SIZE).
        self.max_request_size = max_request_size()
        self.rejected = 0
        self._queue: deque = deque()
        self._zenoh = node.context.session.declare_queryable(
            service_key(node.context.domain_id, name), self._on_query, complete=True)
        super().__init__(node, EntityKind.SERVICE, name, srv_type, qos)
        others = [e for e in self._servers(self._entity.type) if e != self._entity]
        if others and warn_if_shared:
            node.get_logger().warn(
                f"service '{name}' is already served by {', '.join(sorted(e.node_fqn for e in others))}: "
                'clients will reach only one of the servers')

    @property
    def service_name(self) -> str:
        """The fully qualified (remapped) name this service serves."""
        return self.srv_name

    def _servers(self, type_name: str) -> list:
        """Servers of this name and type in the graph: endpoints are typed, as in ROS 2, so
        servers of different types may share a name and each answers its own requests."""
        return [e for e in self._node.context.graph.entities()
                if e.kind == EntityKind.SERVICE and e.name == self.srv_name and e.type == type_name]

    # Zenoh thread: queue the query untouched (it is read on the executor).
    def _on_query(self, query: Any) -> None:
        if len(self._queue) >= _MAX_PENDING:
            query.reply_err(f"service '{self.srv_name}' is overloaded ({_MAX_PENDING} requests waiting)".encode())
            query.drop()
            return
        self._queue.append(query)
        if not self._scheduled:
            self._schedule()

    # Executor thread: one request per call. An async callback's coroutine is returned, for the
    # executor to run as a task; it answers the query when it ends.
    def _execute(self) -> Any:
        try:
            query = self._queue.popleft()
        except IndexError:
            query = None
        self._rearm()
        if query is None:
            return None
        outcome = None
        try:
            outcome = self._answer(query)
        finally:
            if outcome is None:
                query.drop()
            elif isinstance(outcome, DeferredResponse):
                outcome._bind(query)
        return outcome if inspect.iscoroutine(outcome) else None

    def _refuse(self, query: Any, reason: str) -> None:
        """Answer a request that never reaches the callback, and count it."""
        self.rejected += 1
        query.reply_err(f"service '{self.srv_name}' refused the request: {reason}".encode())

    def _answer(self, query: Any) -> Any:
        payload = query.payload
        if payload is not None and len(payload) > self.max_request_size:  # refused before it is copied
            self._refuse(query, f'the request of {len(payload)} bytes is larger than the limit of '
                                f'{self.max_request_size} bytes')
            return None
        attachment = query.attachment
        attachment = attachment.to_bytes() if attachment is not None else b''
        header = read_header(attachment)
        if header is not None and header[3] != self._tail:
            if self._servers(describe_type(header[3])[0]):
                return None  # a server of the request's type answers it
            self._refuse(query, mismatch_reason(header[3], self.srv_type, 'the client'))
            return None
        old = foreign_protocol(attachment) if header is None else None
        if old is not None:
            self._refuse(query, old)
            return None
        try:
            request = deserialize(payload.to_bytes() if payload is not None else b'', self.srv_type.Request)
        except DecodeError as exc:
            self._refuse(query, str(exc))
            return None
        if self._introspection is not None:
            self._introspection.record(REQUEST_RECEIVED, call_origin(attachment), request=request)
        try:
            response = self.callback(request, self.srv_type.Response())
        except Exception as exc:  # noqa: BLE001 - report to the client and keep serving
            self._callback_failed(query, exc)
            return None
        if inspect.iscoroutine(response):
            return self._answer_later(query, response)
        return self._reply(query, response)

    async def _answer_later(self, query: Any, pending: Any) -> None:
        """Await an async callback, then answer (the query is held open meanwhile)."""
        outcome = None
        try:
            try:
                response = await pending
            except Exception as exc:  # noqa: BLE001 - report to the client and keep serving
                self._callback_failed(query, exc)
                return
            outcome = self._reply(query, response)
        finally:
            if outcome is None:
                query.drop()
            else:
                outcome._bind(query)

    def _callback_failed(self, query: Any, exc: Exception) -> None:
        self._node.get_logger().error(f"service '{self.srv_name}' callback raised {type(exc).__name__}: {exc}")
        query.reply_err(f'{type(exc).__name__}: {exc}'.encode())

    def _reply(self, query: Any, response: Any) -> DeferredResponse | None:
        if isinstance(response, DeferredResponse):
            return response
        if type(response) is not self.srv_type.Response:
            text = (f"service '{self.srv_name}' callback returned {type(response).__name__}, "
                    f'expected {self.srv_type._TYPE} Response')
            query.reply_err(text.encode())
            # A bug in the server, not in a request: the client is told, and spin raises it, as rclpy.
            raise TypeError(text)
        query.reply(query.key_expr, serialize(response))
        if self._introspection is not None:
            attachment = query.attachment
            self._introspection.record(RESPONSE_SENT, call_origin(attachment.to_bytes() if attachment else b''),
                                       response=response)
        return self._follow_up(query, response) if self._follow_up is not None else None

    def _release(self) -> None:
        super()._release()
        while self._queue:
            query = self._queue.popleft()
            query.reply_err(f"service '{self.srv_name}' was destroyed".encode())
            query.drop()
