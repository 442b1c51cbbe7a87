"""Simulated time for a node (rclpy.time_source.TimeSource): with `use_sim_time`, /clock
(rosgraph_msgs/msg/Clock) drives the node's ROS clock, and any other ROSClock attached.

The clock is set on Zenoh's thread as each /clock sample arrives, not by an executor callback:
`now()`, `Rate.sleep()` and `sleep_for` then follow simulated time in a script that never
spins, and a callback that runs for long cannot hold the clock back. Every update wakes the
node's executor, whose timers are due by simulated time.
"""
from __future__ import annotations

import weakref
from typing import TYPE_CHECKING, Any

from zros.clock import ROSClock
from zros.entity import NodeEntity
from zros.graph import EntityKind
from zros.message import deserialize
from zros.qos import QoSProfile, ReliabilityPolicy
from zros.wire import is_wake, read_header, type_tail

if TYPE_CHECKING:
    from zros.node import Node

__all__ = ['TimeSource', 'CLOCK_TOPIC', 'USE_SIM_TIME_NAME']

CLOCK_TOPIC = '/clock'
#: The parameter every node declares to choose simulated time (rclpy's name for the name).
USE_SIM_TIME_NAME = 'use_sim_time'
_CLOCK_QOS = QoSProfile(depth=1, reliability=ReliabilityPolicy.BEST_EFFORT)


class _ClockSubscription(NodeEntity):
    """The /clock subscription (in the graph as the node's subscription, like rclpy's)."""

    def __init__(self, node: 'Node', source: 'TimeSource') -> None:
        from interfaces.rosgraph_msgs.msg import Clock as ClockMsg
        from zros.keys import topic_key
        self._msg_type = ClockMsg
        self._tail = type_tail(ClockMsg)
        self._source = source
        self._complained = False
        self._zenoh = node.context.session.declare_subscriber(
            topic_key(node.context.domain_id, CLOCK_TOPIC), self._on_sample)
        super().__init__(node, EntityKind.SUBSCRIPTION, CLOCK_TOPIC, ClockMsg, _CLOCK_QOS)

    # Zenoh thread.
    def _on_sample(self, sample: Any) -> None:
        if is_wake(sample):
            return   # an executor's wake-up for a subscription of /clock (zros.executors)
        attachment = sample.attachment
        header = read_header(attachment.to_bytes()) if attachment is not None else None
        try:
            if header is not None and header[3] != self._tail:
                raise ValueError('a publisher sends another type than rosgraph_msgs/msg/Clock')
            stamp = deserialize(sample.payload.to_bytes(), self._msg_type).clock
        except Exception as exc:  # noqa: BLE001 - a bad sample must not stop the clock
            if not self._complained:
                self._complained = True
                self._node.get_logger().error(f"ignoring samples on '/clock': {exc} (reported once)")
            return
        self._source._set(stamp.sec * 1_000_000_000 + stamp.nanosec)


class TimeSource:
    """Drives ROSClocks from /clock while the node's `use_sim_time` parameter is true (rclpy's
    TimeSource).

    Each node owns one, with the node's clock attached; more can be made, with or without a
    node, and any ROSClock attached to them. Attached clocks read simulated time while ROS time
    is active and system time otherwise; the last /clock time is kept, so a clock attached
    later starts from it.

    :param node: The node whose `use_sim_time` parameter and /clock subscription drive the
        clocks, or None (attach one later with `attach_node`).
    """

    def __init__(self, *, node: 'Node | None' = None) -> None:
        self._clock_sub: _ClockSubscription | None = None
        self._node_ref: weakref.ReferenceType[Node] | None = None
        # A list, not a set: clocks compare by value (rclpy's are hashable handles).
        self._clocks: list[ROSClock] = []
        self._last_time_ns = 0   # the last /clock time; 0 means none arrived yet
        self._ros_time_is_active = False
        if node is not None:
            self.attach_node(node)

    @property
    def ros_time_is_active(self) -> bool:
        """Whether the attached clocks follow /clock (the node's `use_sim_time`)."""
        return self._ros_time_is_active

    @ros_time_is_active.setter
    def ros_time_is_active(self, enabled: bool) -> None:
        enabled = bool(enabled)
        if enabled == self._ros_time_is_active:
            return
        self._ros_time_is_active = enabled
        for clock in list(self._clocks):
            clock._set_ros_time_is_active(enabled)
        if enabled:
            self._subscribe()
        else:
            self._unsubscribe()
            self._wake_executor()

    def attach_node(self, node: 'Node') -> None:
        """Follow `node`'s `use_sim_time` (declared here, false, if the node lacks it), and
        subscribe to /clock through it while that is true. Detaches a node attached before."""
        if self._node_ref is not None:
            self.detach_node()
        self._node_ref = weakref.ref(node)
        if not node.has_parameter(USE_SIM_TIME_NAME):
            node.declare_parameter(USE_SIM_TIME_NAME, False)
        value = node.get_parameter(USE_SIM_TIME_NAME).value
        if isinstance(value, bool):
            self.ros_time_is_active = value
        elif value is not None:
            node.get_logger().error(f"parameter '{USE_SIM_TIME_NAME}' is {value!r}, not a bool: "
                                    'keeping system time')
        node.add_post_set_parameters_callback(self._on_parameters_set)
        if self._ros_time_is_active:
            self._subscribe()

    def detach_node(self) -> None:
        """Stop following the attached node: its /clock subscription goes, the clocks keep
        their state and the last time."""
        node = self._get_node()
        self._unsubscribe()
        if node is not None:
            try:
                node.remove_post_set_parameters_callback(self._on_parameters_set)
            except ValueError:
                pass   # the node was destroyed and dropped its callbacks
        self._node_ref = None

    def attach_clock(self, clock: ROSClock) -> None:
        """Drive `clock` from now on: it takes the last /clock time and this source's state.

        :raises ValueError: If `clock` is not a ROSClock (only ROS time follows /clock).
        """
        if not isinstance(clock, ROSClock):
            raise ValueError('only ROSClocks (clock type ROS_TIME) can be attached to a TimeSource')
        clock._apply(self._ros_time_is_active, self._last_time_ns)
        clock._add_listener(self._wake_executor)
        if all(c is not clock for c in self._clocks):
            self._clocks.append(clock)

    def _get_node(self) -> 'Node | None':
        return self._node_ref() if self._node_ref is not None else None

    def _on_parameters_set(self, parameters: list[Any]) -> None:
        for param in parameters:
            if param.name == USE_SIM_TIME_NAME and isinstance(param.value, bool):
                self.ros_time_is_active = param.value

    def _subscribe(self) -> None:
        node = self._get_node()
        if self._clock_sub is None and node is not None:
            self._clock_sub = node._add(_ClockSubscription(node, self))

    def _unsubscribe(self) -> None:
        node = self._get_node()
        if self._clock_sub is not None and node is not None:
            node._destroy_entity(self._clock_sub)
        self._clock_sub = None

    # Zenoh thread.
    def _set(self, nanoseconds: int) -> None:
        self._last_time_ns = nanoseconds
        if self._ros_time_is_active:
            for clock in list(self._clocks):
                clock._apply(True, nanoseconds)

    def _wake_executor(self) -> None:
        node = self._get_node()
        executor = node._executor if node is not None else None
        if executor is not None:
            executor.wake()
