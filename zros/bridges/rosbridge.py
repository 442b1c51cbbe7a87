"""The rosbridge v2 protocol over the zros graph: what roslib and other web clients speak.

One `Rosbridge` per bridge node owns the zros entities the clients share (a topic advertised
by several clients has one publisher); one `ClientSession` per connected client turns that
client's operations (subscribe, publish, call_service, advertise_service, send_action_goal, ...)
into zros calls and zros events into frames for it. The transport (zros.bridges.websocket) only
moves frames: a session is handed a `send(frame, key, queue_length)` function that must not
block, since it is called from the executor's threads.

Errors are the client's, never the bridge's: a frame that is not JSON, an unknown op, a type
that does not exist, a message that does not fit its type, a service that is not there -- each
gets a `status` message (level error, with the operation's id) to that client only, and the
bridge and the other clients go on. Protocol: ROSBRIDGE_PROTOCOL.md in RobotWebTools/rosbridge_suite.
"""
from __future__ import annotations

import itertools
import json
import threading
import time
from typing import TYPE_CHECKING, Any, Callable

from zros.bridges.message_json import message_from_json, message_to_json
from zros.errors import ZrosError

if TYPE_CHECKING:
    from zros.node import Node

__all__ = ['Rosbridge', 'ClientSession', 'ProtocolError', 'encode_frame', 'STATUS_LEVELS']

#: set_level's levels, least to most verbose; a status is sent when its level is at most the client's.
STATUS_LEVELS = ('none', 'error', 'warning', 'info')
#: What a send function gets: (frame, queue key, queue length); a key's frames beyond the length drop oldest.
Send = Callable[[Any, 'str | None', int], None]
_SUBSCRIPTION_DEPTH = 100


class ProtocolError(ZrosError):
    """A client's operation cannot be carried out; its text goes back in a status message."""


def encode_frame(message: dict, compression: str = 'none') -> str | bytes:
    """A protocol message as a text frame (JSON) or, with compression 'cbor', a binary one."""
    if compression == 'cbor':
        import cbor2
        return cbor2.dumps(message)
    return json.dumps(message, separators=(',', ':'), allow_nan=False)


def _required(op: dict, key: str, kind: type = str) -> Any:
    value = op.get(key)
    if not isinstance(value, kind) or (kind is str and not value):
        raise ProtocolError(f"'{op.get('op')}' needs a '{key}' ({kind.__name__})")
    return value


class _TopicSubscription:
    """One client's subscription to a topic: its ids (each with a throttle rate and queue length),
    merged as rosbridge does (the lowest throttle, the longest queue), and its zros subscription."""

    def __init__(self) -> None:
        self.ids: dict[str | None, tuple[float, int, str]] = {}
        self.handle: Any = None
        self.last_sent = 0.0

    def settings(self) -> tuple[float, int, str]:
        rates, lengths, compressions = zip(*self.ids.values())
        return min(rates), max(lengths), compressions[-1]


class Rosbridge:
    """The bridge's shared state over one zros node (which the caller spins).

    Args:
        node: the bridge node; entities for every client are made on it.
        max_message_size: frames larger than this [bytes] are refused with a status error.
    """

    def __init__(self, node: 'Node', *, max_message_size: int = 10_000_000) -> None:
        from zros.callback_groups import ReentrantCallbackGroup
        self.node = node
        self.max_message_size = max_message_size
        self.group = ReentrantCallbackGroup()
        self._lock = threading.Lock()
        self._publishers: dict[str, tuple[Any, set]] = {}   # topic -> (publisher, advertising sessions)
        self._session_ids = itertools.count(1)
        self._open: set[int] = set()

    def open_session(self, send: Send) -> 'ClientSession':
        """A session for a newly connected client; `close()` it when the client goes."""
        session = ClientSession(self, send, next(self._session_ids))
        with self._lock:
            self._open.add(session.number)
        return session

    def session_closed(self, session: 'ClientSession') -> None:
        with self._lock:
            self._open.discard(session.number)

    @property
    def sessions(self) -> int:
        """How many clients are connected."""
        return len(self._open)

    def now(self) -> Any:
        """The bridge clock's time as builtin_interfaces/Time (sim time under use_sim_time)."""
        return self.node.get_clock().now().to_msg()

    # -- shared publishers ----------------------------------------------------------------------
    def advertise(self, session: 'ClientSession', topic: str, type_name: str) -> None:
        msg_type = _message_type(type_name)
        with self._lock:
            entry = self._publishers.get(topic)
            if entry is None:
                known = self.topic_types(topic)
                if known and msg_type._TYPE not in known:
                    raise ProtocolError(f"topic '{topic}' already has type {known[0]}, not {msg_type._TYPE}")
                publisher = self.node.create_publisher(msg_type, topic, 10, callback_group=self.group)
                entry = self._publishers[topic] = (publisher, set())
            elif entry[0].msg_type is not msg_type:
                raise ProtocolError(f"topic '{topic}' is advertised with type {entry[0].msg_type._TYPE}, "
                                    f'not {msg_type._TYPE}')
            entry[1].add(session.number)

    def unadvertise(self, session: 'ClientSession', topic: str) -> bool:
        with self._lock:
            entry = self._publishers.get(topic)
            if entry is None or session.number not in entry[1]:
                return False
            entry[1].discard(session.number)
            if not entry[1]:
                del self._publishers[topic]
                self.node.destroy_publisher(entry[0])
            return True

    def publisher(self, topic: str) -> Any:
        with self._lock:
            entry = self._publishers.get(topic)
        return entry and entry[0]

    # -- the graph -------------------------------------------------------------------------------
    def topic_types(self, topic: str) -> list[str]:
        return dict(self.node.get_topic_names_and_types()).get(topic, [])

    def service_types(self, service: str) -> list[str]:
        return dict(self.node.get_service_names_and_types()).get(service, [])


def _message_type(type_name: str) -> type:
    return _interface(type_name, 'msg')


def _interface(type_name: str, kind: str) -> Any:
    """The zros class of a rosbridge type name ('pkg/Name' or 'pkg/kind/Name')."""
    from zros.typesupport import get_action, get_message, get_service, normalize_type_name
    getter = {'msg': get_message, 'srv': get_service, 'action': get_action}[kind]
    if not isinstance(type_name, str) or not type_name:
        raise ProtocolError(f'a {kind} type is needed, got {type_name!r:.40}')
    parts = type_name.strip('/').split('/')
    if len(parts) == 2:
        parts.insert(1, kind)
    try:
        return getter(normalize_type_name('/'.join(parts)))
    except (ZrosError, ImportError, ValueError) as exc:
        raise ProtocolError(f"unknown {kind} type '{type_name}': {exc}") from None


class ClientSession:
    """One connected client; made by Rosbridge.open_session.

    `handle(frame)` runs on the transport's thread, one frame at a time; zros callbacks (messages,
    service responses, goal results) run on the executor's threads and only call `send`.
    """

    def __init__(self, bridge: Rosbridge, send: Send, number: int) -> None:
        self.bridge = bridge
        self.number = number
        self._send = send
        self._lock = threading.Lock()
        self._level = STATUS_LEVELS.index('error')
        self._subscriptions: dict[str, _TopicSubscription] = {}
        self._advertised: set[str] = set()
        self._services: dict[str, Any] = {}                  # advertised service name -> zros Service
        self._pending_requests: dict[str, Any] = {}          # call id -> DeferredResponse
        self._request_ids = itertools.count(1)
        self._service_clients: dict[tuple[str, str], Any] = {}   # (service, type) -> zros Client
        self._action_clients: dict[tuple[str, str], Any] = {}
        self._goals: dict[str, Any] = {}                     # goal id -> ClientGoalHandle (None until accepted)
        self._closed = False

    # -- frames in ---------------------------------------------------------------------------
    def handle(self, frame: str | bytes) -> None:
        """Carry out one frame from the client; every failure becomes a status error to it."""
        op: dict = {}
        try:
            if len(frame) > self.bridge.max_message_size:
                raise ProtocolError(f'message of {len(frame)} bytes is larger than max_message_size '
                                    f'({self.bridge.max_message_size} bytes); dropped')
            op = _decode_frame(frame)
            handler = _OPS.get(op.get('op'))
            if handler is None:
                raise ProtocolError(f"unknown op '{op.get('op')}'" if 'op' in op else "message has no 'op' field")
            handler(self, op)
        except ProtocolError as exc:
            self.status('error', str(exc), op.get('id'))
        except ZrosError as exc:
            self.status('error', f"{op.get('op')}: {exc}", op.get('id'))
        except Exception as exc:  # noqa: BLE001 - a client's frame must never stop the bridge
            self.bridge.node.get_logger().error(f"client {self.number}: '{op.get('op')}' failed: {exc!r}")
            self.status('error', f"{op.get('op')}: internal error: {exc}", op.get('id'))

    def status(self, level: str, text: str, op_id: Any = None) -> None:
        if STATUS_LEVELS.index(level) > self._level:
            return
        message = {'op': 'status', 'level': level, 'msg': text}
        if op_id is not None:
            message['id'] = op_id
        self._send_message(message)

    def _send_message(self, message: dict, compression: str = 'none', key: str | None = None,
                      queue_length: int = 0) -> None:
        if self._closed:
            return
        try:
            frame = encode_frame(message, compression)
        except ValueError as exc:  # not representable (NaN only where JSON has no room for it)
            frame = encode_frame({'op': 'status', 'level': 'error', 'msg': f'cannot encode message: {exc}'})
        self._send(frame, key, queue_length)

    # -- status ------------------------------------------------------------------------------
    def _set_level(self, op: dict) -> None:
        level = op.get('level')
        if level in STATUS_LEVELS:
            self._level = STATUS_LEVELS.index(level)

    # -- topics ------------------------------------------------------------------------------
    def _subscribe(self, op: dict) -> None:
        topic = self.bridge.node.resolve_topic_name(_required(op, 'topic'))
        type_name = op.get('type') or self._inferred_type(topic)
        msg_type = _message_type(type_name)
        compression = op.get('compression') or 'none'
        if compression not in ('none', 'cbor') or (compression == 'cbor' and not _has_cbor()):
            self.status('warning', f"compression '{compression}' is not supported here; sending JSON "
                        '(CBOR needs the cbor2 package: pip install zros[bridge])', op.get('id'))
            compression = 'none'
        throttle = _number(op, 'throttle_rate') / 1000.0
        queue_length = int(_number(op, 'queue_length'))
        with self._lock:
            sub = self._subscriptions.get(topic)
            if sub is not None and sub.handle.msg_type is not msg_type:
                raise ProtocolError(f"topic '{topic}' is already subscribed with type {sub.handle.msg_type._TYPE}")
            if sub is None:
                sub = self._subscriptions[topic] = _TopicSubscription()
            sub.ids[op.get('id')] = (throttle, queue_length, compression)
            if sub.handle is None:
                def deliver(msg: Any) -> None:
                    self._on_message(topic, msg)
                sub.handle = self.bridge.node.create_subscription(
                    msg_type, topic, deliver, self._subscription_qos(topic), callback_group=self.bridge.group)

    def _inferred_type(self, topic: str) -> str:
        types = self.bridge.topic_types(topic)
        if not types:
            raise ProtocolError(f"cannot infer the type of topic '{topic}': it is not advertised yet; give 'type'")
        return types[0]

    def _subscription_qos(self, topic: str) -> Any:
        """What the publishers offer, as `ros2 topic echo` adapts: reliable and transient local
        (a latched /map) when every publisher offers it, else best effort (a sensor's /scan)
        and volatile. Deep enough for a burst: what a slow client cannot take is dropped by its
        send queue, counted."""
        from zros.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
        offers = [info.qos_profile for info in self.bridge.node.get_publishers_info_by_topic(topic)]
        reliable = not offers or all(q.reliability == ReliabilityPolicy.RELIABLE for q in offers)
        latched = bool(offers) and all(q.durability == DurabilityPolicy.TRANSIENT_LOCAL for q in offers)
        return QoSProfile(depth=_SUBSCRIPTION_DEPTH,
                          reliability=ReliabilityPolicy.RELIABLE if reliable else ReliabilityPolicy.BEST_EFFORT,
                          durability=DurabilityPolicy.TRANSIENT_LOCAL if latched else DurabilityPolicy.VOLATILE)

    def _on_message(self, topic: str, msg: Any) -> None:  # executor thread
        with self._lock:
            sub = self._subscriptions.get(topic)
            if sub is None or not sub.ids:
                return
            throttle, queue_length, compression = sub.settings()
            now = time.monotonic()
            if throttle and now - sub.last_sent < throttle:
                return
            sub.last_sent = now
        self._send_message({'op': 'publish', 'topic': topic, 'msg': message_to_json(msg)},
                           compression, f'topic:{topic}', queue_length)

    def _unsubscribe(self, op: dict) -> None:
        topic = self.bridge.node.resolve_topic_name(_required(op, 'topic'))
        with self._lock:
            sub = self._subscriptions.get(topic)
            if sub is None:
                return
            if op.get('id') is not None:
                sub.ids.pop(op['id'], None)
            else:
                sub.ids.clear()
            if sub.ids:
                return
            del self._subscriptions[topic]
        self.bridge.node.destroy_subscription(sub.handle)

    def _advertise(self, op: dict) -> None:
        topic = self.bridge.node.resolve_topic_name(_required(op, 'topic'))
        self.bridge.advertise(self, topic, _required(op, 'type'))
        self._advertised.add(topic)

    def _unadvertise(self, op: dict) -> None:
        topic = self.bridge.node.resolve_topic_name(_required(op, 'topic'))
        if not self.bridge.unadvertise(self, topic):
            self.status('warning', f"topic '{topic}' is not advertised by this client", op.get('id'))
        self._advertised.discard(topic)

    def _publish(self, op: dict) -> None:
        topic = self.bridge.node.resolve_topic_name(_required(op, 'topic'))
        if topic not in self._advertised:  # rosbridge advertises on first publish when it knows the type
            self._advertise({'op': 'advertise', 'topic': topic, 'type': op.get('type') or self._inferred_type(topic)})
        publisher = self.bridge.publisher(topic)
        publisher.publish(message_from_json(publisher.msg_type, op.get('msg'), now=self.bridge.now))

    # -- services ----------------------------------------------------------------------------
    def _call_service(self, op: dict) -> None:
        service = self.bridge.node.resolve_service_name(_required(op, 'service'))
        op_id = op.get('id')
        types = self.bridge.service_types(service)
        if not types and not op.get('type'):
            raise ProtocolError(f"service '{service}' does not exist")
        srv_type = _interface(op.get('type') or types[0], 'srv')
        request = message_from_json(srv_type.Request, _service_args(srv_type.Request, op.get('args')),
                                    now=self.bridge.now)
        timeout = op.get('timeout')
        with self._lock:
            client = self._service_clients.get((service, srv_type._TYPE))
            if client is None:
                client = self._service_clients[(service, srv_type._TYPE)] = self.bridge.node.create_client(
                    srv_type, service, callback_group=self.bridge.group)
        future = client.call_async(request, timeout_sec=timeout if isinstance(timeout, (int, float)) and timeout > 0
                                   else None)

        def on_done(done: Any) -> None:
            response = {'op': 'service_response', 'service': service}
            if op_id is not None:
                response['id'] = op_id
            exc = done.exception()
            if exc is None:
                response.update(values=message_to_json(done.result()), result=True)
            else:
                response.update(values=str(exc), result=False)
            self._send_message(response)
        future.add_done_callback(on_done)

    def _advertise_service(self, op: dict) -> None:
        from zros.service import DeferredResponse
        service = self.bridge.node.resolve_service_name(_required(op, 'service'))
        srv_type = _interface(_required(op, 'type'), 'srv')
        with self._lock:
            if service in self._services:
                old = self._services.pop(service)
                self.bridge.node.destroy_service(old)

        def on_request(request: Any, _response: Any) -> DeferredResponse:  # executor thread
            deferred = DeferredResponse()
            call_id = f'service_request:{service}:{next(self._request_ids)}'
            with self._lock:
                self._pending_requests[call_id] = (deferred, srv_type)
            self._send_message({'op': 'call_service', 'id': call_id, 'service': service,
                                'args': message_to_json(request)})
            return deferred
        with self._lock:
            self._services[service] = self.bridge.node.create_service(
                srv_type, service, on_request, callback_group=self.bridge.group)

    def _service_response(self, op: dict) -> None:
        call_id = _required(op, 'id')
        with self._lock:
            pending = self._pending_requests.pop(call_id, None)
        if pending is None:
            raise ProtocolError(f"no service request with id '{call_id}' is waiting for a response")
        deferred, srv_type = pending
        if op.get('result') is False:
            deferred.fail(f"the web client serving '{op.get('service')}' failed: {op.get('values')}")
            return
        try:
            deferred.resolve(message_from_json(srv_type.Response, op.get('values'), now=self.bridge.now))
        except ZrosError as exc:
            deferred.fail(str(exc))
            raise

    def _unadvertise_service(self, op: dict) -> None:
        service = self.bridge.node.resolve_service_name(_required(op, 'service'))
        with self._lock:
            handle = self._services.pop(service, None)
        if handle is None:
            self.status('warning', f"service '{service}' is not advertised by this client", op.get('id'))
            return
        self.bridge.node.destroy_service(handle)

    # -- actions -----------------------------------------------------------------------------
    def _send_action_goal(self, op: dict) -> None:
        from zros.action import ActionClient
        action = self.bridge.node.resolve_service_name(_required(op, 'action'))
        action_type = _interface(_required(op, 'action_type'), 'action')
        goal = message_from_json(action_type.Goal, _service_args(action_type.Goal, op.get('args')),
                                 now=self.bridge.now)
        goal_id = op.get('id') or f'send_action_goal:{action}:{next(self._request_ids)}'
        with self._lock:
            client = self._action_clients.get((action, action_type._TYPE))
            if client is None:
                client = self._action_clients[(action, action_type._TYPE)] = ActionClient(
                    self.bridge.node, action_type, action, callback_group=self.bridge.group)
            self._goals[goal_id] = None
        base = {'id': goal_id, 'action': action}

        def on_feedback(feedback: Any) -> None:
            self._send_message({'op': 'action_feedback', **base, 'values': message_to_json(feedback.feedback)})

        def on_result(done: Any) -> None:
            with self._lock:
                self._goals.pop(goal_id, None)
            exc = done.exception()
            if exc is not None:
                self._send_message({'op': 'action_result', **base, 'values': str(exc), 'status': 6, 'result': False})
                return
            response = done.result()
            self._send_message({'op': 'action_result', **base, 'values': message_to_json(response.result),
                                'status': int(response.status), 'result': True})

        def on_accepted(done: Any) -> None:
            exc = done.exception()
            handle = None if exc is not None else done.result()
            if handle is None or not handle.accepted:
                with self._lock:
                    self._goals.pop(goal_id, None)
                reason = str(exc) if exc is not None else 'the goal was rejected'
                self.status('error', f"action '{action}': {reason}", goal_id)
                self._send_message({'op': 'action_result', **base, 'values': reason, 'status': 6, 'result': False})
                return
            with self._lock:
                cancel_asked = self._goals.get(goal_id) == 'cancel'
                self._goals[goal_id] = handle
            if cancel_asked:
                handle.cancel_goal_async()
            handle.get_result_async().add_done_callback(on_result)
        future = client.send_goal_async(goal, feedback_callback=on_feedback if op.get('feedback') else None)
        future.add_done_callback(on_accepted)

    def _cancel_action_goal(self, op: dict) -> None:
        goal_id = _required(op, 'id')
        with self._lock:
            if goal_id not in self._goals:
                raise ProtocolError(f"no goal with id '{goal_id}' is in progress")
            handle = self._goals[goal_id]
            if handle is None or handle == 'cancel':
                self._goals[goal_id] = 'cancel'   # cancelled once accepted
                return
        handle.cancel_goal_async()

    def _not_supported(self, op: dict) -> None:
        raise ProtocolError(f"'{op['op']}' is not supported by zros's rosbridge_server")

    # -- end -----------------------------------------------------------------------------------
    def close(self) -> None:
        """The client went: undo its subscriptions, advertisements and services, fail its
        pending service requests. Idempotent."""
        with self._lock:
            if self._closed:
                return
            self._closed = True
            subscriptions, self._subscriptions = list(self._subscriptions.values()), {}
            services, self._services = list(self._services.values()), {}
            pending, self._pending_requests = list(self._pending_requests.values()), {}
            action_clients, self._action_clients = list(self._action_clients.values()), {}
            service_clients, self._service_clients = list(self._service_clients.values()), {}
        node = self.bridge.node
        for client in service_clients:
            node.destroy_client(client)
        for sub in subscriptions:
            node.destroy_subscription(sub.handle)
        for service in services:
            node.destroy_service(service)
        for deferred, _ in pending:
            deferred.fail('the web client serving this service disconnected')
        for client in action_clients:
            client.destroy()
        for topic in list(self._advertised):
            self.bridge.unadvertise(self, topic)
        self.bridge.session_closed(self)


def _decode_frame(frame: str | bytes) -> dict:
    """A client frame as an op dict: JSON text, or CBOR in a binary frame."""
    try:
        if isinstance(frame, bytes):
            import cbor2
            op = cbor2.loads(frame)
        else:
            op = json.loads(frame)
    except Exception as exc:  # noqa: BLE001 - json and cbor2 raise several kinds for bad input
        raise ProtocolError(f'message is not valid {"CBOR" if isinstance(frame, bytes) else "JSON"}: {exc}') from None
    if not isinstance(op, dict):
        raise ProtocolError('message must be a JSON object with an \'op\' field')
    return op


def _has_cbor() -> bool:
    import importlib.util
    return importlib.util.find_spec('cbor2') is not None


def _number(op: dict, key: str) -> float:
    value = op.get(key) or 0
    if isinstance(value, bool) or not isinstance(value, (int, float)) or value < 0:
        raise ProtocolError(f"'{key}' must be a number >= 0, got {value!r:.40}")
    return float(value)


def _service_args(request_type: type, args: Any) -> Any:
    """rosbridge's args are an object of fields, or a list of the fields' values in order."""
    if isinstance(args, list):
        names = list(request_type._FIELDS)
        if len(args) > len(names):
            raise ProtocolError(f'{len(args)} args given, {request_type._TYPE} has {len(names)} fields')
        return dict(zip(names, args))
    return args


_OPS: dict[str, Callable[[ClientSession, dict], None]] = {
    'set_level': ClientSession._set_level,
    'subscribe': ClientSession._subscribe,
    'unsubscribe': ClientSession._unsubscribe,
    'advertise': ClientSession._advertise,
    'unadvertise': ClientSession._unadvertise,
    'publish': ClientSession._publish,
    'call_service': ClientSession._call_service,
    'service_response': ClientSession._service_response,
    'advertise_service': ClientSession._advertise_service,
    'unadvertise_service': ClientSession._unadvertise_service,
    'send_action_goal': ClientSession._send_action_goal,
    'cancel_action_goal': ClientSession._cancel_action_goal,
    'advertise_action': ClientSession._not_supported,
    'unadvertise_action': ClientSession._not_supported,
    'fragment': ClientSession._not_supported,
    'auth': ClientSession._not_supported,
}
