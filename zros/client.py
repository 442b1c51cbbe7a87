"""Service clients: a request is one Zenoh get; its reply completes a Future.

Replies complete the future on Zenoh's thread, so a blocking `call()` works even from inside
a callback of a single-threaded executor (rclpy deadlocks there); the reply is decoded by the
thread that reads the future, not by Zenoh's. Done-callbacks still run on the node's executor.
A call fails with ServiceCallError when the server raises or refuses the request, when it
disappears (Zenoh finalizes the query at once), or after `timeout_sec`.

A server is ready when the graph lists it and Zenoh's routing knows its queryable: the
liveliness token that puts a server in the graph can arrive before the queryable's declaration
does, and a request sent in between reaches no one. So `wait_for_service` means a request
sent now is delivered, as in ROS 2, where it returns only once client and server are matched.
A request made before that, by a client that has never reached a server (a test that calls at
once, a node started beside its server), waits for the route, up to its timeout or
SERVER_WAIT_SEC, and fails with a one-line error if no server comes: rclpy would hang on it
forever, and failing at once would lose a call that a server starting a moment later could
answer. Once a client has reached a server, a call with none fails at once: the server went
away (a lifecycle manager must learn that a node crashed now, not in ten seconds).
"""
from __future__ import annotations

import threading
import time
from typing import TYPE_CHECKING, Any, Generic, Iterator

from zros.entity import NodeEntity
from zros.errors import DecodeError, ServiceCallError
from zros.graph import EntityKind
from zros.message import Srv, SrvRequestT, SrvResponseT, deserialize, serialize
from zros.qos import QoSProfile
from zros.service_introspection import REQUEST_SENT, RESPONSE_RECEIVED, Introspectable, call_origin
from zros.task import Future
from zros.wire import AttachmentWriter, max_message_size

if TYPE_CHECKING:
    from zros.node import Node

__all__ = ['Client']

# rclpy's call_async has no timeout; Zenoh needs one. A day is "never" for a request, and a
# server that dies still fails the call at once.
_NO_TIMEOUT = 86_400.0

# How long a request waits for a server to be reachable before it is sent (see the docstring).
SERVER_WAIT_SEC = 10.0


class Client(Introspectable, NodeEntity, Generic[SrvRequestT, SrvResponseT]):
    """Calls one service; made by `Node.create_client`.

    Generic in the service type: `call` and `call_async` take its Request and give its
    Response. Each request is one Zenoh query (see the module docstring).
    """

    def __init__(self, node: 'Node', srv_type: type[Srv[SrvRequestT, SrvResponseT]], name: str, qos: QoSProfile,
                 callback_group: Any) -> None:
        from zros.keys import service_key
        self.srv_type: Any = srv_type   # a class built at run time: its _TYPE is not declared
        self.srv_name = name
        self.qos_profile = qos
        self.callback_group = callback_group
        self._key = service_key(node.context.domain_id, name)
        self._stamp = AttachmentWriter(srv_type).next
        self._max_reply = max_message_size()
        self._route_lock = threading.Lock()
        self._routed: threading.Event | None = None
        self._ever_routed = False
        self._route_handles: tuple[Any, ...] = ()
        super().__init__(node, EntityKind.CLIENT, name, srv_type, qos)

    @property
    def service_name(self) -> str:
        """The fully qualified (remapped) name of the service this client calls."""
        return self.srv_name

    def _servers(self, entities: list) -> list:
        return [e for e in entities if e.kind == EntityKind.SERVICE and e.name == self.srv_name]

    def _route(self) -> threading.Event:
        """An event set while Zenoh's routing knows a queryable on this service's key, kept by a
        matching listener declared on first use (a client never asked whether it is ready pays
        nothing)."""
        with self._route_lock:
            if self._routed is None:
                routed = threading.Event()
                querier = self._node.context.session.declare_querier(self._key)

                def on_matching(status: Any) -> None:  # Zenoh thread
                    if status.matching:
                        self._ever_routed = True
                        routed.set()
                    else:
                        routed.clear()
                listener = querier.declare_matching_listener(on_matching)
                if querier.matching_status.matching:
                    self._ever_routed = True
                    routed.set()
                self._route_handles = (listener, querier)
                self._routed = routed
            return self._routed

    def service_is_ready(self) -> bool:
        """Tell whether a request sent now would reach a server.

        Unlike rcl, which only looks at the graph, zros also asks Zenoh's routing whether it knows
        the server's queryable yet (see the module docstring).

        :return: ``True`` when a server is in the graph and routed to.
        """
        return bool(self._servers(self._node.context.graph.entities())) and self._route().is_set()

    def wait_for_service(self, timeout_sec: float | None = None) -> bool:
        """Wait until a server exists and a request sent now would reach it.

        It waits on graph and routing changes, not by polling.

        :param timeout_sec: Seconds to wait at most; ``None`` waits forever.
        :return: ``True`` if a server is ready, ``False`` on timeout.
        """
        deadline = None if timeout_sec is None else time.monotonic() + timeout_sec
        routed = self._route()
        graph = self._node.context.graph
        while True:
            left = None if deadline is None else max(0.0, deadline - time.monotonic())
            if not graph.wait_for(lambda entities: bool(self._servers(entities)), left):
                return False
            left = None if deadline is None else max(0.0, deadline - time.monotonic())
            if not routed.wait(left):
                return False
            if self.service_is_ready():  # the server may have gone while the route came up
                return True

    def _check(self, request: Any) -> None:
        if type(request) is not self.srv_type.Request:
            raise TypeError(f"client of '{self.srv_name}' expects {self.srv_type._TYPE} Request, "
                            f'got {getattr(type(request), "_TYPE", type(request).__name__)}')
        if self._destroyed:
            raise RuntimeError(f"client of '{self.srv_name}' has been destroyed")

    def _send(self, request: Any, timeout_sec: float | None, handler: Any = None,
              parameters: str = '', stamp: bytes | None = None) -> tuple[float, Any]:
        """Issue the Zenoh get for `request`, already `_check`ed by the caller: (timeout used,
        reply receiver or None).

        With no handler, Zenoh's default FIFO channel holds the replies for the caller.
        `parameters` go in the selector (`key?parameters`) for servers that read them. `stamp`
        is the attachment, when the caller needs to know the call's sequence number first."""
        import zenoh
        timeout = _NO_TIMEOUT if timeout_sec is None else max(0.001, timeout_sec)
        stamp = stamp or self._stamp()
        if self._introspection is not None:
            self._introspection.record(REQUEST_SENT, call_origin(stamp), request=request)
        receiver = self._node.context.session.get(
            f'{self._key}?{parameters}' if parameters else self._key, handler,
            payload=serialize(request), attachment=stamp,
            timeout=timeout, consolidation=zenoh.ConsolidationMode.NONE)
        return timeout, receiver

    def _received(self, origin: tuple[bytes, int], outcome: Any) -> None:
        """Introspection's last step of a call: its response arrived (a failed call has none)."""
        if self._introspection is not None and not isinstance(outcome, Exception):
            self._introspection.record(RESPONSE_RECEIVED, origin, response=outcome)

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

    def _no_server(self, started: float, timeout: float) -> ServiceCallError:
        waited = time.monotonic() - started
        if waited >= timeout * 0.99:
            return ServiceCallTimeout(f"service '{self.srv_name}' did not answer: no server appeared "
                                      f'within the timeout of {waited:.2f} s')
        return ServiceCallError(f"service '{self.srv_name}' has no server: none appeared within {waited:.1f} s "
                                '(is its node running? wait_for_service() waits longer)')

    def _no_answer(self, started: float, timeout: float) -> ServiceCallError:
        waited = time.monotonic() - started
        if waited >= timeout * 0.99:
            return ServiceCallTimeout(f"service '{self.srv_name}' did not answer: timed out after {waited:.2f} s")
        return ServiceCallError(f"service '{self.srv_name}' did not answer: the server went away before "
                                f'answering (or none is running) after {waited:.2f} s')

    def call_async(self, request: SrvRequestT, *, timeout_sec: float | None = None) -> Future[SrvResponseT]:
        """Send a request and return at once.

        The reply is decoded where the future is read (`result()`, an ``await``, a done callback
        on the executor), not on Zenoh's thread. With no server reachable yet, the request is sent
        once one is (see the module docstring).

        :param request: An instance of the service's Request type.
        :param timeout_sec: A zros addition: fail the future after this many seconds (rclpy waits
            forever; ``None`` waits a day).
        :return: A Future completed with the Response, or with a ServiceCallError.
        :raises TypeError: If `request` is not the service's Request.
        :raises RuntimeError: If the client has been destroyed.
        """
        import zenoh
        self._check(request)
        future = _ReplyFuture(self, time.monotonic())
        # Known before the query is sent: with no server, Zenoh may call on_done before _send returns.
        timeout = _NO_TIMEOUT if timeout_sec is None else max(0.001, timeout_sec)

        def on_done() -> None:
            if not future.done():
                future.set_exception(self._no_answer(future._started, timeout))

        def send() -> None:
            left = timeout - (time.monotonic() - future._started)
            stamp = self._stamp()
            future._origin = call_origin(stamp)   # before the reply can arrive
            self._send(request, max(0.001, left), zenoh.handlers.Callback(future._arrive, on_done), stamp=stamp)

        routed = self._route()
        if routed.is_set() or self._ever_routed:
            send()
            return future

        def send_when_routed() -> None:  # a thread of its own: rare (start-up), and may wait long
            try:
                if not routed.wait(min(timeout, SERVER_WAIT_SEC)):
                    future.set_exception(self._no_server(future._started, timeout))
                    return
                send()
            except Exception as exc:  # noqa: BLE001 - destroyed or closed meanwhile: the future says so
                if not future.done():
                    future.set_exception(exc)
        threading.Thread(target=send_when_routed, name=f'call {self.srv_name}', daemon=True).start()
        return future

    def call(self, request: SrvRequestT, timeout_sec: float | None = None) -> SrvResponseT | None:
        """Send a request and block until the response comes.

        The reply is read from Zenoh's channel on this thread, so no executor needs to spin and
        the call works inside a callback (rclpy deadlocks there on a single-threaded executor).

        :param request: An instance of the service's Request type.
        :param timeout_sec: Seconds to wait at most; ``None`` waits a day.
        :return: The Response, or ``None`` if no answer came within `timeout_sec` (rclpy's
            contract, which callers test for).
        :raises ServiceCallError: If the server failed or went away, or (`timeout_sec` None) no
            server appeared within SERVER_WAIT_SEC.
        :raises TypeError: If `request` is not the service's Request.
        """
        try:
            return next(self._replies(request, timeout_sec, (self.srv_type.Response,)))
        except ServiceCallTimeout:
            return None

    def _replies(self, request: Any, timeout_sec: float | None, response_types: tuple[type, ...],
                 parameters: str = '') -> Iterator[Any]:
        """Blocking: send `request`, then yield its replies, decoded as `response_types` in
        order (a server may answer one query more than once). Raises ServiceCallError for a
        failed reply, or when the query ends before a reply expected."""
        started = time.monotonic()
        self._check(request)
        timeout = _NO_TIMEOUT if timeout_sec is None else max(0.001, timeout_sec)
        routed = self._route()
        if not self._ever_routed and not routed.wait(min(timeout, SERVER_WAIT_SEC)):
            raise self._no_server(started, timeout)
        stamp = self._stamp()
        _, receiver = self._send(request, max(0.001, timeout - (time.monotonic() - started)),
                                 parameters=parameters, stamp=stamp)
        replies = iter(receiver)
        for response_type in response_types:
            reply = next(replies, None)
            outcome = (self._no_answer(started, timeout) if reply is None
                       else self._outcome(reply, started, response_type))
            self._received(call_origin(stamp), outcome)
            if isinstance(outcome, Exception):
                raise outcome
            yield outcome


    def _release(self) -> None:
        super()._release()
        for handle in self._route_handles:
            try:
                handle.undeclare()
            except Exception:  # noqa: BLE001 - the session may be closing already
                pass
        self._route_handles = ()


class _ReplyFuture(Future[Any]):
    """The future of a `call_async`. Zenoh's thread only stores the reply and completes the
    future, so waiters wake as before (a thread blocked on it, `spin_until_future_complete`)
    and a callback that waits for it without spinning still sees it complete; the reply is
    decoded once, by the first thread that reads the outcome."""

    def __init__(self, client: Client, started: float) -> None:
        super().__init__(node=client._node)
        self._client = client
        self._started = started
        self._origin = (bytes(16), 0)   # the call's (client gid, sequence), for introspection
        self._reply: Any = None
        self._decode_lock = threading.Lock()

    def _arrive(self, reply: Any) -> None:  # Zenoh thread: no decoding here
        if self.done():
            return
        self._reply = reply
        self.set_result(None)
        if self._client._introspection is not None:
            self._decode()   # the response is received now, whether or not anyone reads it

    def _decode(self) -> None:
        with self._decode_lock:
            reply = self._reply
            if reply is None:
                return  # decoded by another thread meanwhile
            outcome = self._client._outcome(reply, self._started)
            self._client._received(self._origin, outcome)
            if isinstance(outcome, Exception):
                self._exception = outcome
            else:
                self._result = outcome
            self._reply = None   # last: a reader that saw it pending waits for the lock

    def result(self) -> Any:
        if self._reply is not None:
            self._decode()
        return super().result()

    def exception(self) -> BaseException | None:
        if self._reply is not None:
            self._decode()
        return super().exception()


class ServiceCallTimeout(ServiceCallError, TimeoutError):
    """`Client.call` with a timeout raises this (rclpy's `call` returns None; docs/porting.md)."""
