"""Node: a factory and registry for the entities one participant in the graph owns.

Entities own their Zenoh handles and liveliness tokens; the node only keeps the list and
destroys them in one loop. Names go through remapping (`--ros-args -r`) and validation here,
so nothing unvalidated ever reaches zros.keys.
"""
from __future__ import annotations

from typing import TYPE_CHECKING, Any, Callable, Iterable

from zros.callback_groups import CallbackGroup, MutuallyExclusiveCallbackGroup, ReentrantCallbackGroup
from zros.clock import ROSClock
from zros.context import Context, get_default_context
from zros.errors import NotInitializedError
from zros.handle import Handle, HandleOwner
from zros.graph import Entity, EntityKind, endpoints, entity_token, names_and_types, node_names_and_namespaces
from zros.logging import RcutilsLogger, add_sink, get_logger, remove_sink
from zros.message import MsgT, Srv, SrvRequestT, SrvResponseT
from zros.names import (Remappings, expand_topic_name, fully_qualified_node_name, normalize_namespace,
                        validate_node_name)
from zros.arguments import parse_ros_args
from zros.client import Client
from zros.event_handler import PublisherEventCallbacks, SubscriptionEventCallbacks, attach_event_callbacks
from zros.parameter import Parameter, parameter_value_to_python
from zros.parameter_store import ParameterStore
from zros.publisher import Publisher
from zros.qos_overriding_options import (QoSOverridingOptions, declare_qos_parameters,
                                         parameter_events_overriding_options)
from zros.qos import (QoSProfile, qos_profile_default, qos_profile_parameter_events,
                      qos_profile_services_default, to_profile)
from zros.service import Service
from zros.subscription import Subscription, SubscriptionCallback, subscription_lists_changed
from zros.guard_condition import GuardCondition
from zros.timer import Rate, Timer, timer_lists_changed
from zros.time_source import TimeSource
from zros.type_description_service import TypeDescriptionService
from zros.topic_endpoint_info import TopicEndpointInfo
from zros.type_support import is_message_type, is_service_type
from zros.waitable import Waitable, waitable_lists_changed

if TYPE_CHECKING:
    from zros.qos_monitor import QoSMonitor

__all__ = ['Node']


class Node(HandleOwner):
    """A participant in the ROS graph, as rclpy.node.Node: the factory and owner of its entities.

    Create publishers, subscriptions, services, clients, timers and parameters through its
    methods; they live until destroyed one by one or with the node. Where rclpy talks to rcl
    through handles, a zros node announces itself and each entity with a Zenoh liveliness
    token, which is what other participants' graph queries (`zros node list`) see. Use it as a
    context manager, or call `destroy_node()`, to leave the graph.

    :param node_name: The node's name (remapped by ``--ros-args -r __node:=``).
    :param context: The context to run in; the default context (``zros.init()``) if ``None``.
    :param cli_args: ROS arguments for this node only (``['--ros-args', '-p', 'x:=1']``).
    :param namespace: The node's namespace; ``None`` for the root (or the ``__ns`` remap).
    :param use_global_arguments: Also apply the ROS arguments given to ``zros.init()``.
    :param enable_rosout: Publish the node's log lines on /rosout.
    :param start_parameter_services: Serve the parameter services `zros param` uses.
    :param parameter_overrides: Parameters that override the declared defaults.
    :param allow_undeclared_parameters: Let parameters be set without being declared.
    :param automatically_declare_parameters_from_overrides: Declare every overridden parameter.
    :param enable_logger_service: Serve get_logger_levels/set_logger_levels.
    :param parameter_event_qos_overrides: A zros addition; see `__init__`.
    :raises NotInitializedError: If the context is not initialized.
    :raises InvalidNameError: If the node name or namespace is not a valid ROS name.
    """

    def __init__(self, node_name: str, *, context: Context | None = None, cli_args: list[str] | None = None,
                 namespace: str | None = None, use_global_arguments: bool = True,
                 enable_rosout: bool = True, start_parameter_services: bool = True,
                 parameter_overrides: list | None = None, allow_undeclared_parameters: bool = False,
                 automatically_declare_parameters_from_overrides: bool = False,
                 enable_logger_service: bool = False, parameter_event_qos_overrides: bool = False) -> None:
        """rclpy's arguments, and one of zros's own:

        Args:
            parameter_event_qos_overrides: declare the read-only parameters
                `qos_overrides./parameter_events.publisher.{depth,durability,history,reliability}`
                as every rclcpp node does, so that `zros param list` shows a node that stands in
                for a C++ one (turtlesim) as `ros2 param list` shows the original. Values given
                at start-up (`-p`, a parameter file) set the QoS of its /parameter_events publisher.
        """
        self._context = context or get_default_context()
        if not self._context.ok():
            raise NotInitializedError('zros is not initialized: call zros.init() before creating a node')
        validate_node_name(node_name)
        self._remappings = Remappings()
        arg_sets = []
        if cli_args:
            arg_sets.append(parse_ros_args(['--ros-args', *cli_args] if '--ros-args' not in cli_args else cli_args))
        if use_global_arguments:
            arg_sets.append(self._context.ros_args)
        for args in arg_sets:  # node-local rules first: the first matching rule wins
            for rule in args.remaps:
                self._remappings.add(rule)
        self._ros_args = arg_sets
        new_name, new_ns = self._remappings.node_overrides(node_name)
        self._original_name = node_name
        self._name = validate_node_name(new_name or node_name)
        self._namespace = normalize_namespace(new_ns if new_ns is not None else namespace)
        self._logger = get_logger(self._logger_name())
        self._clock = ROSClock()
        self._default_callback_group = MutuallyExclusiveCallbackGroup()
        self._rate_group: CallbackGroup | None = None   # rates' timers, apart from other callbacks
        self._executor: Any = None
        self._unseen_completions = 0
        self._entities: list[Any] = []
        self._timers: list[Timer] = []
        self._waitables: list[Waitable] = []
        self._tokens: dict[int, Any] = {}
        self._qos_monitor: QoSMonitor | None = None
        self._node_id = self._context.next_id()
        self._zid = str(self._context.session.info.zid())
        self._destroyed = False
        self._handle = Handle(f"node '{self._name}'")
        self._node_entity = Entity(EntityKind.NODE, self._zid, self._node_id, 0, self._namespace, self._name)
        self._node_token = self._declare_token(self._node_entity)
        self._context._register_node(self)
        self._rosout: Publisher[Any] | None = None
        self._rosout_sink: Callable[..., None] | None = None
        if enable_rosout and not any(a.disable_rosout for a in arg_sets):
            self._start_rosout()
        self._parameters = ParameterStore(
            self, overrides=ParameterStore.collect_overrides(self.get_fully_qualified_name(), arg_sets,
                                                             parameter_overrides),
            allow_undeclared=allow_undeclared_parameters)
        events_qos = declare_qos_parameters(
            Publisher, self, '/parameter_events', qos_profile_parameter_events,
            parameter_events_overriding_options() if parameter_event_qos_overrides else None)
        events: Publisher[Any] = Publisher(self, _type('rcl_interfaces/msg/ParameterEvent'), '/parameter_events',
                                           events_qos, self._default_callback_group)
        self._entities.append(events)   # listed in `publishers`, as rclpy lists its own
        self._parameters.attach_event_publisher(events)
        # Declares use_sim_time and follows it: with it, ROS time, timers and rates follow /clock.
        self._time_source = TimeSource(node=self)
        self._time_source.attach_clock(self._clock)
        self._type_description = TypeDescriptionService(self)
        if automatically_declare_parameters_from_overrides:
            for name, value in self._parameters.overrides.items():
                if not self.has_parameter(name):
                    self.declare_parameter(name, value)
        if start_parameter_services:
            from zros.parameter_service import ParameterService
            ParameterService(self)
        if enable_logger_service:
            from zros.logging_service import LoggingService
            LoggingService(self)

    # -- identity --------------------------------------------------------------------------
    def _logger_name(self) -> str:
        ns = self._namespace.strip('/').replace('/', '.')
        return f'{ns}.{self._name}' if ns else self._name

    def get_name(self) -> str:
        """The node's name (after remapping)."""
        return self._name

    def get_namespace(self) -> str:
        """The node's namespace, always starting with ``/``."""
        return self._namespace

    def get_fully_qualified_name(self) -> str:
        """The namespace and name joined, e.g. ``/robot1/talker``."""
        return fully_qualified_node_name(self._namespace, self._name)

    @property
    def context(self) -> Context:
        """The context the node runs in (its Zenoh session and domain)."""
        return self._context

    @property
    def executor(self) -> Any:
        """The executor that spins this node, or ``None``.

        Setting it moves the node from its current executor to the new one.
        """
        return self._executor

    @executor.setter
    def executor(self, executor: Any) -> None:
        if executor is self._executor:
            return
        if self._executor is not None:
            self._executor.remove_node(self)
        if executor is not None:
            executor.add_node(self)
        self._executor = executor   # add_node/remove_node set it too; any executor-like object works

    @property
    def default_callback_group(self) -> CallbackGroup:
        """The mutually exclusive group of entities created without a `callback_group`.

        So a node's callbacks never run at the same time unless you put them in other groups.
        """
        return self._default_callback_group

    def get_logger(self) -> RcutilsLogger:
        """The node's logger, named after its namespace and name (lines also go to /rosout)."""
        return self._logger

    def get_clock(self) -> ROSClock:
        """The node's ROSClock: system time, or /clock while `use_sim_time` is true."""
        return self._clock

    def resolve_topic_name(self, topic: str, *, only_expand: bool = False) -> str:
        """Expand a topic name against this node and apply remapping.

        :param topic: A relative (``chatter``), private (``~/chatter``) or absolute name.
        :param only_expand: Expand only; skip the ``-r`` remapping rules.
        :return: The fully qualified name.
        :raises InvalidNameError: If the name is not a valid ROS name.
        """
        return self._resolve(topic, 'topic name', only_expand)

    def resolve_service_name(self, service: str, *, only_expand: bool = False) -> str:
        """Expand a service name against this node and apply remapping, as resolve_topic_name.

        :raises InvalidServiceNameException: If the name is not a valid ROS name.
        """
        return self._resolve(service, 'service name', only_expand)

    def _resolve(self, name: str, kind: str, only_expand: bool) -> str:
        fq = expand_topic_name(name, self._name, self._namespace, kind)
        if only_expand:
            return fq
        return self._remappings.apply(fq, self._name, self._namespace, self._original_name)

    # -- entities --------------------------------------------------------------------------
    def _declare_token(self, entity: Entity) -> Any:
        token = self._context.session.liveliness().declare_token(entity_token(self._context.domain_id, entity))
        self._context.graph.add_local(entity)
        return token

    def _declare_entity(self, kind: str, name: str, iface_type: Any, qos: QoSProfile | None = None) -> Entity:
        """Announce an entity in the graph; returns its record (kept by the entity)."""
        entity = Entity(kind, self._zid, self._node_id, self._context.next_id(), self._namespace, self._name,
                        name, iface_type._TYPE, iface_type._HASH, qos.to_token() if qos else '')
        self._tokens[entity.entity_id] = self._declare_token(entity)
        return entity

    def _undeclare_entity(self, entity: Entity) -> None:
        token = self._tokens.pop(entity.entity_id, None)
        if self._context.ok():
            self._context.graph.remove_local(entity)
        if token is not None:
            self._context._undeclare(token)

    def _add(self, entity: Any) -> Any:
        self._entities.append(entity)
        if isinstance(entity, Subscription):
            subscription_lists_changed()
        if self._qos_monitor is None and isinstance(entity, (Publisher, Subscription)):
            from zros.qos_monitor import QoSMonitor
            self._qos_monitor = QoSMonitor(self)
        elif self._qos_monitor is not None and isinstance(entity, (Publisher, Subscription)):
            self._qos_monitor.check()
        if self._executor is not None:
            self._executor.wake()
        return entity

    def _forget(self, entity: Any) -> bool:
        """Drop `entity` from the registry (it is being destroyed by its owner)."""
        if entity in self._entities:
            self._entities.remove(entity)
            if isinstance(entity, Subscription):
                subscription_lists_changed()
            if entity in self._timers:
                self._timers.remove(entity)
                timer_lists_changed()
            return True
        return False

    def _destroy_entity(self, entity: Any) -> bool:
        if self._forget(entity):
            entity.destroy()
            for handler in getattr(entity, 'event_handlers', ()):
                self._destroy_entity(handler)
            return True
        return False

    def _check_alive(self) -> None:
        if self._destroyed:
            raise RuntimeError(f"node '{self._name}' has been destroyed")

    def create_publisher(self, msg_type: type[MsgT], topic: str, qos_profile: QoSProfile | int = qos_profile_default,
                         *, callback_group: CallbackGroup | None = None,
                         event_callbacks: PublisherEventCallbacks | None = None,
                         qos_overriding_options: QoSOverridingOptions | None = None,
                         publisher_class: type[Publisher[Any]] = Publisher) -> Publisher[MsgT]:
        """Create a publisher of `msg_type` messages on `topic`.

        zros declares a Zenoh publisher on the topic's key (an advanced publisher with a cache when
        the QoS is transient local) and a liveliness token that puts it in the graph.

        :param msg_type: The message class, e.g. ``String`` from ``interfaces.std_msgs.msg``.
        :param topic: The topic name, resolved with `resolve_topic_name`.
        :param qos_profile: A QoSProfile, or a history depth: an int means KEEP_LAST with that
            depth and the default profile's other policies.
        :param callback_group: The group for the publisher's event callbacks; the node's default
            group if ``None``.
        :param event_callbacks: Callbacks for QoS events (deadline missed, liveliness lost,
            incompatible QoS).
        :param qos_overriding_options: Which QoS policies parameters may override at start-up.
        :param publisher_class: The class to instantiate (a lifecycle node passes its own).
        :return: The new publisher, typed by its message class.
        :raises TypeError: If `msg_type` is not a message class, or the QoS is neither a profile
            nor an int.
        :raises RuntimeError: If the node has been destroyed.
        """
        self._check_alive()
        _require_message_type(msg_type)
        topic = self.resolve_topic_name(topic)
        qos = declare_qos_parameters(Publisher, self, topic, to_profile(qos_profile), qos_overriding_options)
        publisher = publisher_class(self, msg_type, topic, qos, callback_group or self._default_callback_group)
        attach_event_callbacks(publisher, event_callbacks or PublisherEventCallbacks())
        return self._add(publisher)

    def create_subscription(self, msg_type: type[MsgT], topic: str, callback: SubscriptionCallback[MsgT],
                            qos_profile: QoSProfile | int = qos_profile_default, *,
                            callback_group: CallbackGroup | None = None,
                            event_callbacks: SubscriptionEventCallbacks | None = None,
                            qos_overriding_options: QoSOverridingOptions | None = None,
                            raw: bool = False) -> Subscription[MsgT]:
        """Create a subscription to `msg_type` messages on `topic`.

        Samples wait undecoded in a queue of the QoS depth; the node's executor decodes each and
        calls `callback` (see zros.subscription for what is dropped and counted, and why).

        :param msg_type: The message class.
        :param topic: The topic name, resolved with `resolve_topic_name`.
        :param callback: Called with each message; a callback taking two positional arguments also
            gets a MessageInfo dict (timestamps, sequence number). An ``async def`` callback runs
            as a task.
        :param qos_profile: A QoSProfile, or a history depth (KEEP_LAST with that depth).
        :param callback_group: The group the callback runs in; the node's default group if ``None``.
        :param event_callbacks: Callbacks for QoS events (deadline missed, liveliness changed,
            message lost, incompatible QoS).
        :param qos_overriding_options: Which QoS policies parameters may override at start-up.
        :param raw: Hand the callback the serialized bytes instead of a message.
        :return: The new subscription, typed by its message class.
        :raises TypeError: If `msg_type` is not a message class or `callback` is not callable.
        :raises RuntimeError: If the node has been destroyed.
        """
        self._check_alive()
        _require_message_type(msg_type)
        if not callable(callback):
            raise TypeError('subscription callback must be callable')
        topic = self.resolve_topic_name(topic)
        qos = declare_qos_parameters(Subscription, self, topic, to_profile(qos_profile), qos_overriding_options)
        subscription = Subscription(self, msg_type, topic, callback, qos,
                                    callback_group or self._default_callback_group, raw=raw)
        attach_event_callbacks(subscription, event_callbacks or SubscriptionEventCallbacks())
        return self._add(subscription)

    def create_timer(self, timer_period_sec: float, callback: Callable[[], Any],
                     callback_group: CallbackGroup | None = None, clock: Any = None,
                     autostart: bool = True) -> Timer:
        """Create a timer that calls `callback` every `timer_period_sec` on the node's executor.

        The first call comes one period after creation. On a clock following /clock the timer
        stops while simulated time stands still.

        :param timer_period_sec: The period [s].
        :param callback: A function of no arguments (or ``async def``).
        :param callback_group: The group the callback runs in; the node's default group if ``None``.
        :param clock: The clock to schedule on; the node's clock if ``None``.
        :param autostart: Start at once; with ``False`` the timer waits for `reset()`.
        :return: The new timer.
        :raises RuntimeError: If the node has been destroyed.
        """
        self._check_alive()
        timer = Timer(callback, callback_group or self._default_callback_group,
                      int(timer_period_sec * 1_000_000_000), clock or self._clock, node=self, autostart=autostart)
        self._timers.append(timer)
        timer_lists_changed()
        return self._add(timer)

    def create_service(self, srv_type: type[Srv[SrvRequestT, SrvResponseT]], srv_name: str,
                       callback: Callable[[SrvRequestT, SrvResponseT], Any], *,
                       qos_profile: QoSProfile = qos_profile_services_default,
                       callback_group: CallbackGroup | None = None,
                       expect_other_servers: bool = False) -> Service[SrvRequestT, SrvResponseT]:
        """Create a server for `srv_name`: `callback(request, response)` fills and returns the response.

        The server is a Zenoh queryable; each request is answered from the node's executor.
        A second server of the same name and type is logged as a warning (clients reach only one
        of them).

        :param srv_type: The service class, e.g. ``AddTwoInts`` from ``interfaces.example_interfaces.srv``.
        :param srv_name: The service name, resolved like a topic name.
        :param callback: Takes the request and a fresh response; returns the response (or a
            DeferredResponse to answer later). An exception it raises fails the client's call.
        :param qos_profile: The QoS profile (kept for the graph; Zenoh queries are reliable).
        :param callback_group: The group the callback runs in; the node's default group if ``None``.
        :param expect_other_servers: A zros addition: several nodes serve this name by design (as
            every tf2 Buffer given a node serves tf2_frames), so do not warn.
        :return: The new service.
        :raises TypeError: If `srv_type` is not a service class.
        :raises RuntimeError: If the node has been destroyed.
        """
        self._check_alive()
        _require_service_type(srv_type)
        return self._add(Service(self, srv_type, self.resolve_service_name(srv_name), callback,
                                 to_profile(qos_profile), callback_group or self._default_callback_group,
                                 warn_if_shared=not expect_other_servers))

    def create_client(self, srv_type: type[Srv[SrvRequestT, SrvResponseT]], srv_name: str, *,
                      qos_profile: QoSProfile = qos_profile_services_default,
                      callback_group: CallbackGroup | None = None) -> Client[SrvRequestT, SrvResponseT]:
        """Create a client of the service `srv_name`.

        :param srv_type: The service class.
        :param srv_name: The service name, resolved like a topic name.
        :param qos_profile: The QoS profile (kept for the graph; Zenoh queries are reliable).
        :param callback_group: The group for done callbacks of its futures; the node's default
            group if ``None``.
        :return: The new client, typed by its service class.
        :raises TypeError: If `srv_type` is not a service class.
        :raises RuntimeError: If the node has been destroyed.
        """
        self._check_alive()
        _require_service_type(srv_type)
        return self._add(Client(self, srv_type, self.resolve_service_name(srv_name), to_profile(qos_profile),
                                callback_group or self._default_callback_group))

    def create_guard_condition(self, callback: Callable[[], Any] | None,
                               callback_group: CallbackGroup | None = None) -> GuardCondition:
        """Create a guard condition: `trigger()` it from any thread to run `callback` on the executor.

        :param callback: A function of no arguments, or ``None``.
        :param callback_group: The group the callback runs in; the node's default group if ``None``.
        :return: The new guard condition.
        :raises RuntimeError: If the node has been destroyed.
        """
        self._check_alive()
        return self._add(GuardCondition(callback, callback_group or self._default_callback_group, node=self))

    def destroy_guard_condition(self, guard: GuardCondition) -> bool:
        """Destroy a guard condition made by this node.

        :param guard: The guard condition.
        :return: ``True`` if the node had it (destroying twice returns ``False``).
        """
        return self._destroy_entity(guard)

    def destroy_service(self, service: Service[Any, Any]) -> bool:
        """Destroy a service made by this node; it leaves the graph and stops answering.

        :param service: The service.
        :return: ``True`` if the node had it.
        """
        return self._destroy_entity(service)

    def destroy_client(self, client: Client[Any, Any]) -> bool:
        """Destroy a client made by this node; its pending calls fail.

        :param client: The client.
        :return: ``True`` if the node had it.
        """
        return self._destroy_entity(client)

    def create_rate(self, frequency: float, clock: Any = None) -> Rate:
        """Create a Rate, to pace a loop in a thread other than the one spinning the node.

        As rclpy's, the rate also puts a timer of its period on the node, in a group of its
        own: an executor spinning the node wakes every period (so a bare `spin_once()` loop
        returns while another thread sleeps on the rate). The rate itself sleeps on its clock
        and needs no spinning.

        :param frequency: Loop frequency [Hz].
        :param clock: The clock to run on; the node's clock if ``None``.
        :return: The new rate.
        :raises TypeError: If `frequency` is not a number.
        :raises ValueError: If it is not positive.
        """
        if isinstance(frequency, bool) or not isinstance(frequency, (int, float)):
            raise TypeError(f'rate frequency must be a number, got {frequency!r}')
        rate = Rate(frequency, clock or self._clock, context=self._context)
        if self._rate_group is None:
            self._rate_group = ReentrantCallbackGroup()
        rate._pacer = self.create_timer(1.0 / frequency, _pace_rate, self._rate_group, clock)
        return rate

    def destroy_publisher(self, publisher: Publisher[Any]) -> bool:
        """Destroy a publisher made by this node; it leaves the graph.

        :param publisher: The publisher.
        :return: ``True`` if the node had it.
        """
        return self._destroy_entity(publisher)

    def destroy_subscription(self, subscription: Subscription[Any]) -> bool:
        """Destroy a subscription made by this node; messages still queued are dropped.

        :param subscription: The subscription.
        :return: ``True`` if the node had it.
        """
        return self._destroy_entity(subscription)

    def destroy_timer(self, timer: Timer) -> bool:
        """Destroy a timer made by this node; its callback is not called again.

        :param timer: The timer.
        :return: ``True`` if the node had it.
        """
        return self._destroy_entity(timer)

    def destroy_rate(self, rate: Rate) -> bool:
        """Destroy a rate; a thread sleeping on it gets RuntimeError.

        :param rate: The rate.
        :return: ``True``.
        """
        rate.destroy()
        return True

    @property
    def publishers(self) -> Iterable[Publisher[Any]]:
        """The node's publishers (a new list each time)."""
        return [e for e in self._entities if isinstance(e, Publisher)]

    @property
    def subscriptions(self) -> Iterable[Subscription[Any]]:
        """The node's subscriptions (a new list each time)."""
        return [e for e in self._entities if isinstance(e, Subscription)]

    @property
    def services(self) -> Iterable[Service[Any, Any]]:
        """The node's services, including its parameter services (a new list each time)."""
        return [e for e in self._entities if isinstance(e, Service)]

    @property
    def clients(self) -> Iterable[Client[Any, Any]]:
        """The node's service clients (a new list each time)."""
        return [e for e in self._entities if isinstance(e, Client)]

    @property
    def guards(self) -> Iterable[GuardCondition]:
        """The node's guard conditions (a new list each time)."""
        return [e for e in self._entities if isinstance(e, GuardCondition)]

    @property
    def timers(self) -> Iterable[Timer]:
        """The node's timers (a new list each time)."""
        return list(self._timers)

    @property
    def waitables(self) -> Iterable[Waitable]:
        """The waitables added with `add_waitable` (a new list each time)."""
        return list(self._waitables)

    def add_waitable(self, waitable: Waitable) -> None:
        """Have the node's executor poll and run a user-defined waitable (zros.waitable).

        :param waitable: An instance of a Waitable subclass.
        """
        self._waitables.append(waitable)
        waitable_lists_changed()
        if self._executor is not None:
            self._executor.wake()

    def remove_waitable(self, waitable: Waitable) -> None:
        """Stop polling a waitable given to `add_waitable`.

        :param waitable: The waitable.
        :raises ValueError: If it was not added.
        """
        self._waitables.remove(waitable)
        waitable_lists_changed()

    def _own_endpoint_objects(self) -> list[Publisher[Any] | Subscription[Any]]:
        return [e for e in list(self._entities) if isinstance(e, (Publisher, Subscription))]

    def _timers_snapshot(self) -> list[Timer]:
        return self._timers[:]

    # -- executor hooks ----------------------------------------------------------------------
    def _attach_executor(self, executor: Any) -> None:
        self._executor = executor
        for entity in self._entities:
            if getattr(entity, '_has_work', None) and entity._has_work():
                executor._enqueue(entity)
        if self._unseen_completions:
            self._unseen_completions = 0
            executor._note_completion()

    def _note_completion(self) -> None:
        """A future of this node completed while no executor had the node: the next executor
        that spins it counts that as work (rclpy's client keeps the response for it)."""
        self._unseen_completions += 1

    def _run_on_executor(self, fn: Callable, *args: Any) -> None:
        """Run `fn(*args)` as a task of this node's executor (inline when it has none)."""
        executor = self._executor
        if executor is None:
            fn(*args)
        else:
            executor.create_task(fn, *args)

    def _detach_executor(self, executor: Any) -> None:
        if self._executor is executor:
            self._executor = None

    # -- graph -----------------------------------------------------------------------------
    def _graph_entities(self) -> list[Entity]:
        return self._context.graph.entities()

    def get_node_names(self) -> list[str]:
        """The names of the nodes in the graph, without namespaces.

        :return: One name per node, this one included.
        """
        return [name for name, _ in node_names_and_namespaces(self._graph_entities())]

    def get_node_names_and_namespaces(self) -> list[tuple[str, str]]:
        """The nodes in the graph.

        :return: ``(name, namespace)`` pairs, sorted.
        """
        return node_names_and_namespaces(self._graph_entities())

    def get_node_names_and_namespaces_with_enclaves(self) -> list[tuple[str, str, str]]:
        """The nodes in the graph with their security enclave.

        zros's graph does not announce enclaves, so each node is listed in the root enclave
        '/' (docs/porting.md).

        :return: ``(name, namespace, enclave)`` triples, sorted.
        """
        return [(name, namespace, '/') for name, namespace in self.get_node_names_and_namespaces()]

    def get_fully_qualified_node_names(self) -> list[str]:
        """The nodes in the graph, as fully qualified names.

        :return: Names such as ``/turtlesim``.
        """
        return [fully_qualified_node_name(ns, n) for n, ns in self.get_node_names_and_namespaces()]

    def get_topic_names_and_types(self, no_demangle: bool = False) -> list[tuple[str, list[str]]]:
        """The topics that have a publisher or subscription in the graph.

        :param no_demangle: Accepted for rclpy's signature; zros names are never mangled.
        :return: ``(topic, [type, ...])`` pairs, sorted by topic.
        """
        return names_and_types(self._graph_entities(), (EntityKind.PUBLISHER, EntityKind.SUBSCRIPTION))

    def get_service_names_and_types(self) -> list[tuple[str, list[str]]]:
        """The services that have a server in the graph.

        :return: ``(service, [type, ...])`` pairs, sorted by service.
        """
        return names_and_types(self._graph_entities(), (EntityKind.SERVICE,))

    def _by_node(self, kind: str, node_name: str, node_namespace: str) -> list[tuple[str, list[str]]]:
        ns = normalize_namespace(node_namespace)
        return names_and_types([e for e in self._graph_entities()
                                if e.node_name == node_name and e.namespace == ns], (kind,))

    def get_publisher_names_and_types_by_node(self, node_name: str, node_namespace: str) -> list:
        """The topic (publisher) names and types that one node has, from the graph.

        :param node_name: The node's name, without namespace.
        :param node_namespace: The node's namespace.
        :return: ``(name, [type, ...])`` pairs, sorted by name.
        """
        return self._by_node(EntityKind.PUBLISHER, node_name, node_namespace)

    def get_subscriber_names_and_types_by_node(self, node_name: str, node_namespace: str) -> list:
        """The topic (subscription) names and types that one node has, from the graph.

        :param node_name: The node's name, without namespace.
        :param node_namespace: The node's namespace.
        :return: ``(name, [type, ...])`` pairs, sorted by name.
        """
        return self._by_node(EntityKind.SUBSCRIPTION, node_name, node_namespace)

    def get_service_names_and_types_by_node(self, node_name: str, node_namespace: str) -> list:
        """The service (server) names and types that one node has, from the graph.

        :param node_name: The node's name, without namespace.
        :param node_namespace: The node's namespace.
        :return: ``(name, [type, ...])`` pairs, sorted by name.
        """
        return self._by_node(EntityKind.SERVICE, node_name, node_namespace)

    def get_client_names_and_types_by_node(self, node_name: str, node_namespace: str) -> list:
        """The service (client) names and types that one node has, from the graph.

        :param node_name: The node's name, without namespace.
        :param node_namespace: The node's namespace.
        :return: ``(name, [type, ...])`` pairs, sorted by name.
        """
        return self._by_node(EntityKind.CLIENT, node_name, node_namespace)

    def count_services(self, service_name: str) -> int:
        """Count the servers of a service in the graph.

        :param service_name: The service name, expanded against this node (not remapped, as rclpy).
        :return: The number of servers.
        """
        return len(endpoints(self._graph_entities(), EntityKind.SERVICE, self.resolve_service_name(service_name, only_expand=True)))

    def count_clients(self, service_name: str) -> int:
        """Count the clients of a service in the graph.

        :param service_name: The service name, expanded against this node (not remapped, as rclpy).
        :return: The number of clients.
        """
        return len(endpoints(self._graph_entities(), EntityKind.CLIENT, self.resolve_service_name(service_name, only_expand=True)))

    def count_publishers(self, topic_name: str) -> int:
        """Count the publishers on a topic in the graph.

        :param topic_name: The topic name, expanded against this node (not remapped, as rclpy).
        :return: The number of publishers.
        """
        return len(endpoints(self._graph_entities(), EntityKind.PUBLISHER, self.resolve_topic_name(topic_name, only_expand=True)))

    def count_subscribers(self, topic_name: str) -> int:
        """Count the subscriptions on a topic in the graph.

        :param topic_name: The topic name, expanded against this node (not remapped, as rclpy).
        :return: The number of subscriptions.
        """
        return len(endpoints(self._graph_entities(), EntityKind.SUBSCRIPTION, self.resolve_topic_name(topic_name, only_expand=True)))

    def get_publishers_info_by_topic(self, topic_name: str, no_mangle: bool = False) -> list[TopicEndpointInfo]:
        """Describe every publisher on a topic: node, type, QoS (what `zros topic info -v` prints).

        :param topic_name: The topic name, resolved against this node.
        :param no_mangle: Accepted for rclpy's signature: zros names are never mangled.
        :return: One TopicEndpointInfo per publisher.
        """
        return self._endpoints_info(EntityKind.PUBLISHER, topic_name)

    def get_subscriptions_info_by_topic(self, topic_name: str, no_mangle: bool = False) -> list[TopicEndpointInfo]:
        """Describe every subscription on a topic: node, type, QoS.

        :param topic_name: The topic name, resolved against this node.
        :param no_mangle: Accepted for rclpy's signature: zros names are never mangled.
        :return: One TopicEndpointInfo per subscription.
        """
        return self._endpoints_info(EntityKind.SUBSCRIPTION, topic_name)

    def _endpoints_info(self, kind: str, topic_name: str) -> list[TopicEndpointInfo]:
        found = endpoints(self._graph_entities(), kind, self.resolve_topic_name(topic_name))
        return [TopicEndpointInfo.from_entity(entity) for entity in found]

    def wait_for_node(self, fully_qualified_node_name: str, timeout: float) -> bool:
        """Wait until a node is in the graph (woken by graph changes, not by polling).

        :param fully_qualified_node_name: E.g. ``/turtlesim``; a missing leading ``/`` is added.
        :param timeout: Seconds to wait at most.
        :return: ``True`` if the node appeared, ``False`` on timeout.
        """
        target = fully_qualified_node_name if fully_qualified_node_name.startswith('/') else '/' + fully_qualified_node_name
        return self._context.graph.wait_for(
            lambda entities: any(e.kind == EntityKind.NODE and e.node_fqn == target for e in entities), timeout)

    # -- parameters (rclpy's API; the rules live in ParameterStore) ----------------------------
    def declare_parameter(self, name: str, value: Any = None, descriptor: Any = None,
                          ignore_override: bool = False) -> Parameter:
        """Declare a parameter, taking its value from the overrides (``-p``, a parameter file) if any.

        :param name: The parameter's name.
        :param value: The default value, or a Parameter.Type to declare a typed parameter with no
            value yet.
        :param descriptor: An rcl_interfaces/msg/ParameterDescriptor (read-only, ranges, dynamic
            typing).
        :param ignore_override: Use `value` even if an override is given.
        :return: The declared parameter.
        :raises ParameterAlreadyDeclaredException: If it is declared already.
        :raises InvalidParameterTypeException: If the override's type differs from the default's.
        :raises InvalidParameterValueException: If a set-parameters callback rejects the value.
        """
        return self._parameters.declare(name, value, descriptor, ignore_override)

    def declare_parameters(self, namespace: str, parameters: list, ignore_override: bool = False) -> list[Parameter]:
        """Declare several parameters under one namespace.

        :param namespace: The prefix, joined to each name with a dot; empty for none.
        :param parameters: ``(name, value)`` or ``(name, value, descriptor)`` tuples.
        :param ignore_override: Use the given values even if overrides are given.
        :return: The declared parameters, in order.
        :raises ParameterAlreadyDeclaredException: If any is declared already (then none is).
        :raises InvalidParameterException: If a name is empty (then none is declared).
        :raises TypeError: If a name is not a str or a descriptor not a ParameterDescriptor.
        """
        from zros.exceptions import InvalidParameterException, ParameterAlreadyDeclaredException
        entries = []
        for entry in parameters:
            name, value, descriptor = (tuple(entry) + (None, None))[:3]
            if not isinstance(name, str):
                raise TypeError(f'parameter name {name!r} is not a str')
            if descriptor is not None and not isinstance(descriptor, _type('rcl_interfaces/msg/ParameterDescriptor')):
                raise TypeError(f'descriptor of parameter {name!r} is not a ParameterDescriptor')
            full = f'{namespace}.{name}' if namespace else name
            if not full:
                raise InvalidParameterException(full)
            entries.append((full, value, descriptor))
        already = [full for full, _, _ in entries if self._parameters.has(full)]
        if already:   # before any is declared, as rclpy
            raise ParameterAlreadyDeclaredException(already)
        declared = []
        for full, value, descriptor in entries:
            if not self._parameters.has(full):   # a name listed twice is declared once, the first time
                self._parameters.declare(full, value, descriptor, ignore_override)
            declared.append(self._parameters.get_or(full))
        return declared

    def undeclare_parameter(self, name: str) -> None:
        """Remove a declared parameter.

        :param name: The parameter's name.
        :raises ParameterNotDeclaredException: If it is not declared.
        :raises ParameterImmutableException: If it is read-only.
        """
        self._parameters.undeclare(name)

    def has_parameter(self, name: str) -> bool:
        """Tell whether a parameter is declared.

        :param name: The parameter's name.
        :return: ``True`` if it is.
        """
        return self._parameters.has(name)

    def get_parameter(self, name: str) -> Parameter:
        """Read a parameter.

        :param name: The parameter's name.
        :return: The parameter (its `.value` is the Python value).
        :raises ParameterNotDeclaredException: If it is not declared (and undeclared parameters
            are not allowed).
        :raises ParameterUninitializedException: If it was declared with a type and no value.
        """
        return self._parameters.get(name)

    def get_parameters(self, names: list[str]) -> list[Parameter]:
        """Read several parameters.

        :param names: The parameters' names.
        :return: The parameters, in order.
        :raises ParameterNotDeclaredException: If one is not declared.
        """
        return [self._parameters.get(n) for n in names]

    def get_parameter_or(self, name: str, alternative_value: Parameter | None = None) -> Parameter:
        """Read a parameter, or fall back to `alternative_value` if it is undeclared or unset.

        :param name: The parameter's name.
        :param alternative_value: The fallback; a NOT_SET parameter if ``None``.
        :return: The parameter or the fallback.
        """
        return self._parameters.get_or(name, alternative_value)

    def get_parameters_by_prefix(self, prefix: str) -> dict[str, Parameter]:
        """Read every parameter under a prefix, keyed by the rest of its name.

        :param prefix: E.g. ``'controller'`` for ``controller.kp``, ``controller.ki``.
        :return: ``{'kp': Parameter, 'ki': Parameter}``.
        """
        dotted = prefix + '.' if prefix else ''
        return {n[len(dotted):]: self._parameters.get(n) for n in self._parameters.names()
                if n.startswith(dotted)}

    def set_parameters(self, parameter_list: list[Parameter]) -> list[Any]:
        """Set parameters one by one; each succeeds or fails on its own.

        :param parameter_list: The new values.
        :return: One rcl_interfaces/msg/SetParametersResult per parameter.
        :raises ParameterNotDeclaredException: If one is not declared (and undeclared parameters
            are not allowed); the ones before it are set already, as in rclpy.
        """
        _require_parameters(parameter_list)
        return self._parameters.set_each(parameter_list, raise_undeclared=True)

    def set_parameters_atomically(self, parameter_list: list[Parameter]) -> Any:
        """Set parameters all together: either every one is set or none is.

        :param parameter_list: The new values.
        :return: One rcl_interfaces/msg/SetParametersResult for the whole set.
        :raises ParameterNotDeclaredException: If one is not declared.
        """
        _require_parameters(parameter_list)
        return self._parameters.set_atomically(parameter_list, raise_undeclared=True)

    def describe_parameter(self, name: str) -> Any:
        """The descriptor of a parameter.

        :param name: The parameter's name.
        :return: An rcl_interfaces/msg/ParameterDescriptor.
        :raises ParameterNotDeclaredException: If it is not declared.
        """
        return self._parameters.describe(name)

    def describe_parameters(self, names: list[str]) -> list[Any]:
        """The descriptors of several parameters.

        :param names: The parameters' names.
        :return: rcl_interfaces/msg/ParameterDescriptor messages, in order.
        """
        return [self._parameters.describe(n) for n in names]

    def set_descriptor(self, name: str, descriptor: Any, alternative_value: Any = None) -> Any:
        """Replace a declared parameter's descriptor (its ranges, constraints, read-only flag).

        The descriptor's name is ignored, and so is its type when it types dynamically (the
        value's type is kept). No set-parameters callbacks run.

        :param name: The parameter's name.
        :param descriptor: The new rcl_interfaces/msg/ParameterDescriptor.
        :param alternative_value: An rcl_interfaces/msg/ParameterValue to take if the current
            value does not meet the new descriptor.
        :return: The parameter's rcl_interfaces/msg/ParameterValue afterwards.
        :raises ParameterNotDeclaredException: If it is not declared (and undeclared are not allowed).
        :raises ParameterImmutableException: If it is read-only.
        :raises InvalidParameterValueException: If neither value meets the descriptor.
        """
        alternative = None
        if alternative_value is not None:
            alternative = Parameter(name, value=parameter_value_to_python(alternative_value))
        return self._parameters.set_descriptor(name, descriptor, alternative).get_parameter_value()

    def list_parameters(self, prefixes: list[str], depth: int) -> Any:
        """The declared parameters' names under `prefixes`, as the ListParameters service answers.

        :param prefixes: Only names equal to or below one of these (all names if empty).
        :param depth: How many levels below the prefix (or the root) to list; 0 lists all.
        :return: An rcl_interfaces/msg/ListParametersResult with `names` and their `prefixes`.
        :raises TypeError: If `prefixes` is not a list of str or `depth` not an int.
        :raises ValueError: If `depth` is negative.
        """
        from interfaces.rcl_interfaces.msg import ListParametersResult
        if not isinstance(prefixes, list) or not all(isinstance(p, str) for p in prefixes):
            raise TypeError('prefixes must be a list of str')
        if not isinstance(depth, int):
            raise TypeError('depth must be an int')
        if depth < 0:
            raise ValueError('depth must be greater than or equal to zero')
        names, found = self._parameters.list(prefixes, depth)
        return ListParametersResult(names=names, prefixes=found)

    def add_on_set_parameters_callback(self, callback: Callable) -> Callable:
        """Register a validator: `callback(parameters)` returns a SetParametersResult; an unsuccessful
        one rejects the whole set.

        :param callback: The validator.
        :return: `callback`, for `remove_on_set_parameters_callback`.
        """
        self._parameters.add_callback('on_set', callback)
        return callback

    def remove_on_set_parameters_callback(self, callback: Callable) -> None:
        """Unregister a validator.

        :param callback: A callback given to `add_on_set_parameters_callback`.
        :raises ValueError: If it is not registered.
        """
        self._parameters.remove_callback('on_set', callback)

    def add_pre_set_parameters_callback(self, callback: Callable) -> Callable:
        """Register a callback that may change the list of parameters about to be set.

        :param callback: Takes the list of Parameters, returns the list to set instead.
        :return: `callback`.
        """
        self._parameters.add_callback('pre_set', callback)
        return callback

    def remove_pre_set_parameters_callback(self, callback: Callable) -> None:
        """Unregister a pre-set callback.

        :param callback: A callback given to `add_pre_set_parameters_callback`.
        :raises ValueError: If it is not registered.
        """
        self._parameters.remove_callback('pre_set', callback)

    def add_post_set_parameters_callback(self, callback: Callable) -> Callable:
        """Register a callback run after parameters were set (to apply them).

        :param callback: Takes the list of Parameters that were set.
        :return: `callback`.
        """
        self._parameters.add_callback('post_set', callback)
        return callback

    def remove_post_set_parameters_callback(self, callback: Callable) -> None:
        """Unregister a post-set callback.

        :param callback: A callback given to `add_post_set_parameters_callback`.
        :raises ValueError: If it is not registered.
        """
        self._parameters.remove_callback('post_set', callback)

    @property
    def _parameter_overrides(self) -> dict[str, Any]:
        return self._parameters.overrides

    # rclpy's Node keeps its callbacks in these lists and code reads them (`cb in node._on_set_
    # parameters_callbacks`); here they are snapshots of the store's, in the order they run.
    @property
    def _pre_set_parameters_callbacks(self) -> tuple[Callable, ...]:
        return self._parameters.callbacks('pre_set')

    @property
    def _on_set_parameters_callbacks(self) -> tuple[Callable, ...]:
        return self._parameters.callbacks('on_set')

    @property
    def _post_set_parameters_callbacks(self) -> tuple[Callable, ...]:
        return self._parameters.callbacks('post_set')

    # -- /rosout ---------------------------------------------------------------------------
    def _start_rosout(self) -> None:
        from interfaces.rcl_interfaces.msg import Log
        self._rosout = Publisher(self, Log, '/rosout', QoSProfile(depth=1000), self._default_callback_group)
        prefix = self._logger.name

        def sink(severity: int, name: str, message: str, time_ns: int, file: str, function: str, line: int) -> None:
            if self._rosout is None or not (name == prefix or name.startswith(prefix + '.')):
                return
            try:
                sec, nsec = divmod(time_ns, 1_000_000_000)
                log = Log(level=int(severity), name=name, msg=message, file=file, function=function, line=line)
                log.stamp.sec, log.stamp.nanosec = sec, nsec
                self._rosout._send(log)
            except Exception:  # noqa: BLE001 - logging must never raise into user code
                pass
        self._rosout_sink = sink
        add_sink(sink)

    # -- teardown ----------------------------------------------------------------------------
    def destroy_node(self) -> None:
        """Undeclare every entity and the node's token (once no `with node.handle:` block holds
        the node); calling it twice is harmless."""
        if self._destroyed:
            return
        self._destroyed = True
        self._handle.destroy_when_not_in_use(self._teardown)

    def _teardown(self) -> None:
        if self._executor is not None:
            self._executor.remove_node(self)
        if self._rosout_sink is not None:
            remove_sink(self._rosout_sink)
        if self._qos_monitor is not None:
            self._qos_monitor.close()
        for entity in list(self._entities):
            self._destroy_entity(entity)
        if self._waitables:
            self._waitables.clear()
            waitable_lists_changed()
        if self._rosout is not None:
            self._rosout.destroy()
            self._rosout = None
        if self._parameters._events is not None:
            self._parameters._events.destroy()
            self._parameters.attach_event_publisher(None)
        if self._context.ok():
            self._context.graph.remove_local(self._node_entity)
        self._context._undeclare(self._node_token)
        self._context._unregister_node(self)

    def __enter__(self) -> 'Node':
        return self

    def __exit__(self, *exc: object) -> None:
        self.destroy_node()

    def __repr__(self) -> str:
        return f'<zros Node {self.get_fully_qualified_name()}>'


def _require_parameters(parameter_list: Any) -> None:
    """rclpy's TypeError for a set_parameters list holding anything but Parameters."""
    for param in parameter_list:
        if not isinstance(param, Parameter):
            raise TypeError(f'parameters must be Parameter instances, got {param!r}')


def _pace_rate() -> None:
    """A rate's timer callback: nothing to do, its firing wakes the executor each period."""


def _type(name: str) -> type:
    from zros.typesupport import get_type
    return get_type(name)


def _require_service_type(srv_type: Any) -> None:
    if not is_service_type(srv_type):
        raise TypeError(f'{srv_type!r} is not a service type (import it from interfaces.<pkg>.srv)')


def _require_message_type(msg_type: Any) -> None:
    if not is_message_type(msg_type):
        raise TypeError(f'{msg_type!r} is not a message class (import it from interfaces.<pkg>.msg)')
