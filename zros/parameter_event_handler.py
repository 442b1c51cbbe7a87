"""React to parameter changes anywhere in the graph (rclpy.parameter_event_handler).

Every node publishes its parameter changes on /parameter_events. A ParameterEventHandler
subscribes once and calls back per parameter of a node, or per event:

    handler = ParameterEventHandler(node)
    handle = handler.add_parameter_callback('background_r', 'turtlesim', on_red)
    handler.remove_parameter_callback(handle)

Callbacks run on the executor that spins `node`, newest first (as rclpy calls them).
"""
from __future__ import annotations

import threading
from collections import defaultdict
from itertools import chain
from typing import TYPE_CHECKING, Any, Callable, Iterator, NamedTuple

from zros.parameter import Parameter
from zros.qos import QoSProfile, qos_profile_parameter_events

if TYPE_CHECKING:
    from zros.callback_groups import CallbackGroup
    from zros.event_handler import SubscriptionEventCallbacks
    from zros.node import Node
    from zros.qos_overriding_options import QoSOverridingOptions

__all__ = ['ParameterCallbackHandle', 'ParameterEventCallbackHandle', 'ParameterEventHandler']


class ParameterCallbackHandle(NamedTuple):
    """What add_parameter_callback returns; give it back to remove the callback."""
    parameter_name: str
    node_name: str    # fully qualified
    callback: Callable[[Parameter], None]


class ParameterEventCallbackHandle(NamedTuple):
    """What add_parameter_event_callback returns; give it back to remove the callback."""
    callback: Callable[[Any], None]


def _parameters(event: Any) -> Iterator[Parameter]:
    """The new and changed parameters of a ParameterEvent, as Parameters."""
    for param in chain(event.new_parameters, event.changed_parameters):
        yield param if isinstance(param, Parameter) else Parameter.from_parameter_msg(param)


class _Callbacks:
    """The registered callbacks, and the dispatch of one event to them.

    Thread-safe: a multi-threaded executor may deliver events while the user adds or removes
    callbacks. The callbacks run outside the lock, on a snapshot, so one may remove itself.
    """

    def __init__(self) -> None:
        self._lock = threading.Lock()
        #: (parameter name, node name) -> handles, newest first
        self.parameter_callbacks: dict[tuple[str, str], list[ParameterCallbackHandle]] = defaultdict(list)
        #: handles, newest first
        self.event_callbacks: list[ParameterEventCallbackHandle] = []

    def event_callback(self, event: Any) -> None:
        """Call the callbacks of each parameter the event carries, then the event callbacks."""
        with self._lock:
            per_parameter = {key: list(handles) for key, handles in self.parameter_callbacks.items()}
            per_event = list(self.event_callbacks)
        for (parameter_name, node_name), handles in per_parameter.items():
            parameter = ParameterEventHandler.get_parameter_from_event(event, parameter_name, node_name)
            if parameter is not None:
                for handle in handles:
                    handle.callback(parameter)
        for handle in per_event:
            handle.callback(event)

    def add_parameter_callback(self, handle: ParameterCallbackHandle) -> ParameterCallbackHandle:
        with self._lock:
            self.parameter_callbacks[(handle.parameter_name, handle.node_name)].insert(0, handle)
        return handle

    def remove_parameter_callback(self, handle: ParameterCallbackHandle) -> None:
        key = (handle.parameter_name, handle.node_name)
        with self._lock:
            handles = self.parameter_callbacks.get(key, [])
            if not any(h is handle for h in handles):
                raise RuntimeError(f"no callback of parameter '{handle.parameter_name}' of {handle.node_name} "
                                   'has this handle (removed already?)')
            handles[:] = [h for h in handles if h is not handle]
            if not handles:
                del self.parameter_callbacks[key]

    def add_parameter_event_callback(self, handle: ParameterEventCallbackHandle) -> ParameterEventCallbackHandle:
        with self._lock:
            self.event_callbacks.insert(0, handle)
        return handle

    def remove_parameter_event_callback(self, handle: ParameterEventCallbackHandle) -> None:
        with self._lock:
            if not any(h is handle for h in self.event_callbacks):
                raise RuntimeError('no parameter event callback has this handle (removed already?)')
            self.event_callbacks[:] = [h for h in self.event_callbacks if h is not handle]


class ParameterEventHandler:
    """One subscription to /parameter_events on `node`, and the callbacks it feeds.

    :param node: The node that subscribes; its executor runs the callbacks.
    :param qos_profile: The subscription's QoS (a profile, or a history depth).
    :param callback_group: The subscription's callback group (the node's default if None).
    :param event_callbacks: QoS event callbacks of the subscription.
    :param qos_overriding_options: Which QoS policies parameters may override.
    :param raw: Deliver events serialized (then only event callbacks make sense).
    """

    def __init__(self, node: 'Node', qos_profile: QoSProfile | int = qos_profile_parameter_events,
                 callback_group: 'CallbackGroup | None' = None,
                 event_callbacks: 'SubscriptionEventCallbacks | None' = None,
                 qos_overriding_options: 'QoSOverridingOptions | None' = None, raw: bool = False) -> None:
        from interfaces.rcl_interfaces.msg import ParameterEvent
        self.node = node
        self.qos_profile = qos_profile
        self._callbacks = _Callbacks()
        self.parameter_event_subscription = node.create_subscription(
            ParameterEvent, '/parameter_events', self._callbacks.event_callback, qos_profile,
            callback_group=callback_group, event_callbacks=event_callbacks,
            qos_overriding_options=qos_overriding_options, raw=raw)

    def destroy(self) -> None:
        """Unsubscribe; no callback runs afterwards."""
        self.node.destroy_subscription(self.parameter_event_subscription)

    @staticmethod
    def get_parameter_from_event(event: Any, parameter_name: str, node_name: str) -> Parameter | None:
        """The new or changed parameter `parameter_name` of `node_name` (fully qualified) in a
        ParameterEvent, or None if the event does not carry it."""
        if event.node != node_name:
            return None
        return next((p for p in _parameters(event) if p.name == parameter_name), None)

    @staticmethod
    def get_parameters_from_event(event: Any) -> Iterator[Parameter]:
        """Every new and changed parameter of a ParameterEvent."""
        return _parameters(event)

    def add_parameter_callback(self, parameter_name: str, node_name: str,
                               callback: Callable[[Parameter], None]) -> ParameterCallbackHandle:
        """Call `callback(parameter)` when `parameter_name` of `node_name` is set or declared.

        :param node_name: A relative name is taken in the namespace of this handler's node.
        :return: The handle for remove_parameter_callback.
        """
        return self._callbacks.add_parameter_callback(
            ParameterCallbackHandle(parameter_name, self._resolve_path(node_name), callback))

    def remove_parameter_callback(self, handle: ParameterCallbackHandle) -> None:
        """Stop calling a parameter callback.

        :raises RuntimeError: If the handle's callback is not registered (any more).
        """
        self._callbacks.remove_parameter_callback(handle)

    def add_parameter_event_callback(self, callback: Callable[[Any], None]) -> ParameterEventCallbackHandle:
        """Call `callback(event)` with every ParameterEvent.

        :return: The handle for remove_parameter_event_callback.
        """
        return self._callbacks.add_parameter_event_callback(ParameterEventCallbackHandle(callback))

    def remove_parameter_event_callback(self, handle: ParameterEventCallbackHandle) -> None:
        """Stop calling an event callback.

        :raises RuntimeError: If the handle's callback is not registered (any more).
        """
        self._callbacks.remove_parameter_event_callback(handle)

    def _resolve_path(self, node_path: str | None = None) -> str:
        """A node's fully qualified name: this node's for none, a relative one in its namespace."""
        if not node_path:
            return self.node.get_fully_qualified_name()
        if node_path.startswith('/'):
            return node_path
        namespace = self.node.get_namespace().rstrip('/')
        return f'{namespace}/{node_path}'
