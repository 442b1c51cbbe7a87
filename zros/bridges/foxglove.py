"""Foxglove's WebSocket protocol over the zros graph: what ROS's foxglove_bridge does for ROS 2.

The server is the `foxglove-sdk` package's (the maintained implementation of both protocol
versions Foxglove clients speak, with per-client send queues that drop the oldest message when
full). This module maps the zros graph onto it:

- every published topic is a channel, with its `ros2msg` schema and `cdr` encoding
  (zros.bridges.foxglove_schema); channels come and go with the graph;
- a channel's first client subscription creates a zros subscription, its last unsubscription
  destroys it; each message is re-encoded once as CDR (zros.bag.cdr) and sent to its clients;
- a client's `cdr` channel becomes a zros publisher of the schema's type;
- zros services are advertised and called with CDR requests and responses;
- parameters are `/node.param`, read and set through each node's parameter services, and
  pushed to subscribed clients from /parameter_events;
- with `use_sim_time`, /clock is sent as the server time; the connection graph is published
  to the clients that ask for it.

Threads: the SDK calls the listener from its own threads. Everything that creates or destroys
zros entities is queued and done by the executor (a guard condition wakes it), so the node is
only touched from the executor's thread; publishing and service calls, which zros allows from
any thread, are made from the SDK's. The CDR codec is shared behind a lock.
"""
from __future__ import annotations

import functools
import queue
import threading
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Callable

from zros.bag.cdr import CDR_ENCODING, CdrCodec
from zros.bridges.foxglove_schema import (allowed, channel_schema, compile_whitelist, full_type_name, is_hidden,
                                          parameter_name, service_schemas, split_parameter_name)

if TYPE_CHECKING:
    from zros.node import Node

__all__ = ['BridgeConfig', 'FoxgloveBridge', 'CAPABILITIES']

#: Capability names of ROS's foxglove_bridge `capabilities` parameter.
CAPABILITIES = ('clientPublish', 'parameters', 'parametersSubscribe', 'services', 'connectionGraph', 'assets')

#: [s] how long a client's service call or parameter request waits for the zros side.
_CALL_TIMEOUT_S = 5.0


@dataclass(frozen=True)
class BridgeConfig:
    """foxglove_bridge's parameters (names and defaults as ROS's foxglove_bridge_launch.xml)."""
    port: int = 8765
    address: str = '0.0.0.0'
    topic_whitelist: tuple[str, ...] = ('.*',)
    param_whitelist: tuple[str, ...] = ('.*',)
    service_whitelist: tuple[str, ...] = ('.*',)
    client_topic_whitelist: tuple[str, ...] = ('.*',)
    send_buffer_limit: int = 10_000_000      # [bytes] a larger message is not sent (counted, reported)
    message_backlog_size: int = 1024         # [messages] per client; the oldest is dropped when full
    capabilities: tuple[str, ...] = CAPABILITIES
    include_hidden: bool = False
    use_sim_time: bool = False
    min_qos_depth: int = 1
    max_qos_depth: int = 10


class _Topic:
    """One advertised topic: its SDK channel and, while a client listens, its zros subscription."""
    __slots__ = ('name', 'type', 'msg_type', 'channel', 'subscription', 'clients', 'oversize')

    def __init__(self, name: str, type_name: str, msg_type: type, channel: Any) -> None:
        self.name, self.type, self.msg_type, self.channel = name, type_name, msg_type, channel
        self.subscription: Any = None
        self.clients: set[int] = set()
        self.oversize = 0


class FoxgloveBridge:
    """Serves the zros graph seen by `node` to Foxglove clients.

    Construct it in the thread that spins `node`'s executor, then spin as usual; `close()`
    stops the server and destroys what the bridge created. Not reusable after close.

    Args:
        node: the bridge's node; the bridge adds a guard condition to it (woken by graph changes
            and by the SDK's requests).
        config: the parameters.
        log: where warnings go (default: the node's logger).
    Raises:
        ValueError: a whitelist pattern or a capability name is invalid.
        RuntimeError: the server cannot start (the SDK's FoxgloveError, e.g. the port is in use).
    """

    def __init__(self, node: 'Node', config: BridgeConfig = BridgeConfig(), *,
                 log: Callable[[str], None] | None = None) -> None:
        import foxglove
        from foxglove.websocket import Capability

        unknown = sorted(set(config.capabilities) - set(CAPABILITIES))
        if unknown:
            raise ValueError(f"unknown capabilities {unknown} (known: {', '.join(CAPABILITIES)})")
        self._node = node
        self._config = config
        self._log = log or node.get_logger().warning
        self._topic_filter = compile_whitelist(config.topic_whitelist)
        self._param_filter = compile_whitelist(config.param_whitelist)
        self._service_filter = compile_whitelist(config.service_whitelist)
        self._client_topic_filter = compile_whitelist(config.client_topic_whitelist)
        self._codec = CdrCodec()
        self._codec_lock = threading.Lock()
        self._topics: dict[str, _Topic] = {}
        self._by_channel: dict[int, _Topic] = {}
        self._services: dict[str, Any] = {}          # name -> zros Client
        self._client_channels: dict[tuple[int, int], tuple[str, type, Any]] = {}
        self._param_clients: dict[str, Any] = {}
        self._warned: set[str] = set()
        self._graph_wanted = False
        self._requests: queue.SimpleQueue[Callable[[], None]] = queue.SimpleQueue()
        self._wake = node.create_guard_condition(self._run_requests)
        self._graph_changed = threading.Event()
        self._graph_changed.set()
        self._context = foxglove.Context()
        capabilities = [Capability.Services] if 'services' in config.capabilities else []
        if 'clientPublish' in config.capabilities:
            capabilities.append(Capability.ClientPublish)
        if {'parameters', 'parametersSubscribe'} & set(config.capabilities):
            capabilities.append(Capability.Parameters)
        if 'connectionGraph' in config.capabilities:
            capabilities.append(Capability.ConnectionGraph)
        if config.use_sim_time:
            capabilities.append(Capability.Time)
        self._capabilities = set(config.capabilities)
        self._server = foxglove.start_server(
            name=node.get_fully_qualified_name(), host=config.address, port=config.port, capabilities=capabilities,
            server_listener=self, supported_encodings=[CDR_ENCODING], context=self._context,
            message_backlog_size=config.message_backlog_size)
        node.context.graph.add_listener(self._on_graph_change)
        self._wake.trigger()   # the first sync
        self._clock_sub = None
        if config.use_sim_time:
            from interfaces.rosgraph_msgs.msg import Clock
            self._clock_sub = node.create_subscription(Clock, '/clock', self._on_clock, 10)
        self._events_sub = None
        if 'parametersSubscribe' in config.capabilities:
            from interfaces.rcl_interfaces.msg import ParameterEvent
            from zros.qos import qos_profile_parameter_events
            self._events_sub = node.create_subscription(ParameterEvent, '/parameter_events', self._on_parameter_event,
                                                        qos_profile_parameter_events)

    @property
    def port(self) -> int:
        """The port the server listens on (the configured one, or the one picked for port 0)."""
        return self._server.port

    def close(self) -> None:
        """Stop the server, then destroy the bridge's zros entities (on the executor's thread, or
        after spinning has stopped). Idempotent."""
        if self._server is None:
            return
        self._node.context.graph.remove_listener(self._on_graph_change)
        self._server.stop()
        self._server = None
        for name in list(self._topics):
            self._drop_topic(name)
        node = self._node
        for client in self._services.values():
            node.destroy_client(client)
        for _, _, publisher in self._client_channels.values():
            node.destroy_publisher(publisher)
        for client in self._param_clients.values():
            client.destroy()
        for subscription in (self._clock_sub, self._events_sub):
            if subscription is not None:
                node.destroy_subscription(subscription)
        node.destroy_guard_condition(self._wake)
        self._services.clear()
        self._client_channels.clear()
        self._param_clients.clear()

    # -- executor side ------------------------------------------------------------------------
    def _on_graph_change(self) -> None:
        self._graph_changed.set()
        self._wake.trigger()

    def _post(self, request: Callable[[], None]) -> None:
        """Run `request` on the executor's thread (called from the SDK's threads)."""
        self._requests.put(request)
        self._wake.trigger()

    def _run_requests(self) -> None:
        """The guard condition's callback: the SDK's queued requests, then a sync if the graph changed."""
        while True:
            try:
                request = self._requests.get_nowait()
            except queue.Empty:
                break
            request()
        self._sync()

    def _sync(self) -> None:
        """Match channels and services to the graph, when it has changed since the last sync."""
        if not self._graph_changed.is_set() or self._server is None:
            return
        self._graph_changed.clear()
        from zros.graph import EntityKind
        entities = self._node.context.graph.entities()
        published: dict[str, set[str]] = {}
        served: dict[str, set[str]] = {}
        for e in entities:
            if e.kind == EntityKind.PUBLISHER:
                published.setdefault(e.name, set()).add(e.type)
            elif e.kind == EntityKind.SERVICE:
                served.setdefault(e.name, set()).add(e.type)
        self._sync_topics(published)
        if 'services' in self._capabilities:
            self._sync_services(served)
        if self._graph_wanted:
            self._publish_graph(entities)

    def _visible(self, name: str, whitelist: list) -> bool:
        return (self._config.include_hidden or not is_hidden(name)) and allowed(name, whitelist)

    def _warn_once(self, key: str, text: str) -> None:
        if key not in self._warned:
            self._warned.add(key)
            self._log(text)

    def _sync_topics(self, published: dict[str, set[str]]) -> None:
        import foxglove
        from zros.typesupport import get_message
        for name in [n for n in self._topics if n not in published]:
            self._drop_topic(name)
        for name, types in sorted(published.items()):
            if name in self._topics or not self._visible(name, self._topic_filter):
                continue
            if len(types) > 1:
                self._warn_once(name, f"not bridging '{name}': it has more than one type ({', '.join(sorted(types))})")
                continue
            type_name = next(iter(types))
            try:
                msg_type = get_message(type_name)
                schema = channel_schema(type_name)
            except Exception as exc:  # noqa: BLE001 - an unknown type skips the topic, not the bridge
                self._warn_once(name, f"not bridging '{name}': {exc}")
                continue
            channel = foxglove.Channel(name, message_encoding=CDR_ENCODING, context=self._context,
                                       schema=foxglove.Schema(name=schema.name, encoding=schema.encoding,
                                                              data=schema.data))
            topic = _Topic(name, type_name, msg_type, channel)
            self._topics[name] = topic
            self._by_channel[channel.id()] = topic

    def _drop_topic(self, name: str) -> None:
        topic = self._topics.pop(name)
        self._by_channel.pop(topic.channel.id(), None)
        if topic.subscription is not None:
            self._node.destroy_subscription(topic.subscription)
        topic.channel.close()

    def _sync_services(self, served: dict[str, set[str]]) -> None:
        import foxglove
        from zros.typesupport import get_service
        gone = [n for n in self._services if n not in served]
        if gone:
            self._server.remove_services(gone)
            for name in gone:
                self._node.destroy_client(self._services.pop(name))
        added = []
        for name, types in sorted(served.items()):
            if name in self._services or not self._visible(name, self._service_filter) or len(types) != 1:
                continue
            type_name = next(iter(types))
            try:
                srv_type = get_service(type_name)
                request, response = service_schemas(type_name)
            except Exception as exc:  # noqa: BLE001 - an unknown type skips the service
                self._warn_once(name, f"not bridging service '{name}': {exc}")
                continue
            self._services[name] = self._node.create_client(srv_type, name)
            schema = foxglove.ServiceSchema(
                type_name,
                request=foxglove.MessageSchema(encoding=CDR_ENCODING, schema=foxglove.Schema(
                    name=request.name, encoding=request.encoding, data=request.data)),
                response=foxglove.MessageSchema(encoding=CDR_ENCODING, schema=foxglove.Schema(
                    name=response.name, encoding=response.encoding, data=response.data)))
            added.append(foxglove.Service(name, schema=schema, handler=self._call_service))
        if added:
            self._server.add_services(added)

    def _publish_graph(self, entities: list) -> None:
        import foxglove
        from zros.graph import EntityKind
        table: dict[str, dict[str, set[str]]] = {EntityKind.PUBLISHER: {}, EntityKind.SUBSCRIPTION: {},
                                                 EntityKind.SERVICE: {}}
        for e in entities:
            if e.kind in table:
                table[e.kind].setdefault(e.name, set()).add(e.node_fqn)
        graph = foxglove.ConnectionGraph()
        for name, nodes in table[EntityKind.PUBLISHER].items():
            graph.set_published_topic(name, sorted(nodes))
        for name, nodes in table[EntityKind.SUBSCRIPTION].items():
            graph.set_subscribed_topic(name, sorted(nodes))
        for name, nodes in table[EntityKind.SERVICE].items():
            graph.set_advertised_service(name, sorted(nodes))
        self._server.publish_connection_graph(graph)

    def _subscribe(self, channel_id: int, client_id: int) -> None:
        topic = self._by_channel.get(channel_id)
        if topic is None:
            return
        topic.clients.add(client_id)
        if topic.subscription is None:
            topic.subscription = self._node.create_subscription(
                topic.msg_type, topic.name, functools.partial(self._forward, topic), self._qos(topic.name))

    def _unsubscribe(self, channel_id: int, client_id: int) -> None:
        topic = self._by_channel.get(channel_id)
        if topic is None:
            return
        topic.clients.discard(client_id)
        if not topic.clients and topic.subscription is not None:
            self._node.destroy_subscription(topic.subscription)
            topic.subscription = None

    def _qos(self, name: str) -> Any:
        """The publishers' reliability and durability (a latched /map reaches a late client), with
        a depth between min_qos_depth and max_qos_depth, as foxglove_bridge picks it."""
        from zros.graph import EntityKind
        from zros.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
        offers = [QoSProfile.from_token(e.qos) for e in self._node.context.graph.entities()
                  if e.kind == EntityKind.PUBLISHER and e.name == name]
        reliable = bool(offers) and all(q.reliability == ReliabilityPolicy.RELIABLE for q in offers)
        transient = bool(offers) and all(q.durability == DurabilityPolicy.TRANSIENT_LOCAL for q in offers)
        depth = max(self._config.min_qos_depth, min(self._config.max_qos_depth, sum(q.depth for q in offers)))
        return QoSProfile(depth=depth,
                          reliability=ReliabilityPolicy.RELIABLE if reliable else ReliabilityPolicy.BEST_EFFORT,
                          durability=DurabilityPolicy.TRANSIENT_LOCAL if transient else DurabilityPolicy.VOLATILE)

    def _forward(self, topic: _Topic, msg: Any) -> None:
        from zros.bag.errors import BagError
        try:
            with self._codec_lock:
                data = self._codec.serialize(msg)
        except (BagError, ValueError, TypeError) as exc:
            self._warn_once(f'{topic.name}#cdr', f"'{topic.name}': a message could not be converted to CDR ({exc})")
            return
        if len(data) > self._config.send_buffer_limit:
            topic.oversize += 1
            if _is_power_of_ten(topic.oversize):   # 1, 10, 100, ...: counted, not one line per message
                self._status(f"'{topic.name}': {topic.oversize} message(s) not sent, larger than "
                             f'send_buffer_limit ({self._config.send_buffer_limit} bytes; the last: {len(data)})')
            return
        topic.channel.log(data)

    def _on_clock(self, msg: Any) -> None:
        if self._server is not None:
            self._server.broadcast_time(msg.clock.sec * 1_000_000_000 + msg.clock.nanosec)

    # -- SDK listener (the SDK's threads) -----------------------------------------------------
    def on_subscribe(self, client: Any, channel: Any) -> None:
        self._post(lambda: self._subscribe(channel.id, client.id))

    def on_unsubscribe(self, client: Any, channel: Any) -> None:
        self._post(lambda: self._unsubscribe(channel.id, client.id))

    def on_client_advertise(self, client: Any, channel: Any) -> None:
        from zros.typesupport import get_message
        if channel.encoding != CDR_ENCODING:
            self._status(f"client channel '{channel.topic}': encoding '{channel.encoding}' is not supported "
                         f"(use '{CDR_ENCODING}')")
            return
        if not allowed(channel.topic, self._client_topic_filter):
            self._status(f"client channel '{channel.topic}' is not in client_topic_whitelist")
            return
        try:
            msg_type = get_message(full_type_name(channel.schema_name))
        except Exception as exc:  # noqa: BLE001 - an unknown type refuses this channel only
            self._status(f"client channel '{channel.topic}': {exc}")
            return
        key = (client.id, channel.id)

        def create() -> None:
            publisher = self._node.create_publisher(msg_type, channel.topic, 10)
            self._client_channels[key] = (channel.topic, msg_type, publisher)
        self._post(create)

    def on_client_unadvertise(self, client: Any, client_channel_id: int) -> None:
        def destroy() -> None:
            entry = self._client_channels.pop((client.id, client_channel_id), None)
            if entry is not None:
                self._node.destroy_publisher(entry[2])
        self._post(destroy)

    def on_message_data(self, client: Any, client_channel_id: int, data: bytes) -> None:
        entry = self._client_channels.get((client.id, client_channel_id))
        if entry is None:
            return
        topic, msg_type, publisher = entry
        from zros.bag.errors import BagError
        try:
            with self._codec_lock:
                msg = self._codec.deserialize(data, msg_type)
        except BagError as exc:
            self._status(f"client message on '{topic}' dropped: {exc}")
            return
        publisher.publish(msg)

    def _call_service(self, request: Any) -> bytes:
        """A client's service call: CDR request in, CDR response out; an error message otherwise
        (the SDK sends it to the calling client as a service call failure)."""
        client = self._services.get(request.service_name)
        if client is None:
            raise RuntimeError(f"service '{request.service_name}' is gone")
        with self._codec_lock:
            zros_request = self._codec.deserialize(request.payload, client.srv_type.Request)
        response = _answer(client.call_async(zros_request))
        if response is None:
            raise RuntimeError(f"service '{request.service_name}' did not answer within {_CALL_TIMEOUT_S:.0f} s")
        with self._codec_lock:
            return self._codec.serialize(response)

    def on_get_parameters(self, client: Any, param_names: list[str], request_id: str | None = None) -> list:
        return self._get_parameters(param_names)

    def on_set_parameters(self, client: Any, parameters: list, request_id: str | None = None) -> list:
        from zros.parameter import Parameter
        by_node: dict[str, list] = {}
        for p in parameters:
            if not self._param_allowed(p.name):
                self._status(f"parameter '{p.name}' not set: not in param_whitelist")
                continue
            try:
                node, name = split_parameter_name(p.name)
                by_node.setdefault(node, []).append(Parameter(name, value=_native(p.get_value())))
            except (ValueError, TypeError) as exc:
                self._status(f"parameter '{p.name}' not set: {exc}")
        for node, params in by_node.items():
            client = self._param_client(node)
            response = None if client is None else _answer(client.set_parameters(params))
            if response is None:
                self._status(f"parameters of '{node}' not set: no answer within {_CALL_TIMEOUT_S:.0f} s")
                continue
            for param, result in zip(params, response.results):
                if not result.successful:
                    self._status(f"parameter '{parameter_name(node, param.name)}' not set: {result.reason}")
        return self._get_parameters([p.name for p in parameters])

    def on_parameters_subscribe(self, param_names: list[str]) -> None:
        return None

    def on_parameters_unsubscribe(self, param_names: list[str]) -> None:
        return None

    def on_connection_graph_subscribe(self) -> None:
        # The SDK forbids publishing the graph from this callback: the next sync does it.
        self._graph_wanted = True
        self._graph_changed.set()
        self._wake.trigger()

    def on_connection_graph_unsubscribe(self) -> None:
        self._graph_wanted = False

    # -- parameters ---------------------------------------------------------------------------
    def _param_client(self, node_fqn: str) -> Any:
        """A parameter client of `node_fqn`, made once on the executor's thread and then called
        from the SDK's; None if the executor did not make it within _CALL_TIMEOUT_S."""
        from zros.parameter_client import AsyncParameterClient
        if node_fqn not in self._param_clients:
            done = threading.Event()

            def create() -> None:
                if node_fqn not in self._param_clients:
                    self._param_clients[node_fqn] = AsyncParameterClient(self._node, node_fqn)
                done.set()
            self._post(create)
            done.wait(_CALL_TIMEOUT_S)
        return self._param_clients.get(node_fqn)

    def _get_parameters(self, names: list[str]) -> list:
        """Parameters by '/node.param' name; all parameters of every node when `names` is empty."""
        from zros.graph import node_names_and_namespaces
        from zros.parameter import parameter_value_to_python
        wanted: dict[str, list[str] | None] = {}
        if names:
            for full in names:
                try:
                    node, param = split_parameter_name(full)
                except ValueError:
                    continue
                entry = wanted.setdefault(node, [])
                entry.append(param)
        else:
            for name, namespace in node_names_and_namespaces(self._node.context.graph.entities()):
                wanted[f"{namespace.rstrip('/')}/{name}"] = None
        result = []
        for node, params in wanted.items():
            client = self._param_client(node)
            if client is None:
                continue
            if params is None:
                listed = _answer(client.list_parameters())
                if listed is None:
                    continue
                params = list(listed.result.names)
            values = _answer(client.get_parameters(params))
            if values is None:
                continue
            for param, value in zip(params, values.values):
                full = parameter_name(node, param)
                if self._param_allowed(full):
                    result.append(_sdk_parameter(full, parameter_value_to_python(value)))
        return result

    def _param_allowed(self, full_name: str) -> bool:
        """param_whitelist matches '/node.param' or, as in ROS's bridge, the parameter's own name."""
        param = full_name.partition('.')[2]
        return allowed(full_name, self._param_filter) or allowed(param, self._param_filter)

    def _on_parameter_event(self, event: Any) -> None:
        from zros.parameter import parameter_value_to_python
        changed = [_sdk_parameter(parameter_name(event.node, p.name), parameter_value_to_python(p.value))
                   for p in list(event.new_parameters) + list(event.changed_parameters)
                   if self._param_allowed(parameter_name(event.node, p.name))]
        if changed and self._server is not None:
            self._server.publish_parameter_values(changed)

    def _status(self, text: str) -> None:
        """Tell the clients (the SDK has no per-client status) and the log."""
        from foxglove import StatusLevel
        self._log(text)
        if self._server is not None:
            self._server.publish_status(text, StatusLevel.Warning)


def _is_power_of_ten(count: int) -> bool:
    return count > 0 and str(count).rstrip('0') == '1'


def _answer(future: Any) -> Any:
    """A zros future's result within _CALL_TIMEOUT_S, or None (no answer, or it failed)."""
    if not future.wait(_CALL_TIMEOUT_S) or future.exception() is not None:
        future.cancel()
        return None
    return future.result()


def _sdk_parameter(name: str, value: Any) -> Any:
    import foxglove
    from foxglove import ParameterType
    if isinstance(value, float):
        return foxglove.Parameter(name, value=value, type=ParameterType.Float64)
    if isinstance(value, list) and value and all(isinstance(v, float) for v in value):
        return foxglove.Parameter(name, value=value, type=ParameterType.Float64Array)
    return foxglove.Parameter(name, value=value)


def _native(value: Any) -> Any:
    """A client's parameter value as ROS types it: bytes stay bytes, tuples become lists."""
    return list(value) if isinstance(value, tuple) else value
