"""Simulated time for a node (rclpy.time_source.TimeSource): with `use_sim_time`, /clock
(rosgraph_msgs/msg/Clock) drives the node's ROS clock.

The clock is set on Zenoh's thread as each /clock sample arrives, not by an executor callback:
`now()`, `Rate.sleep()` and `sleep_for` then follow simulated time in a script that never
spins, and a callback that runs for long cannot hold the clock back. Every update wakes the
node's executor, whose timers are due by simulated time.
"""
from __future__ import annotations

from typing import TYPE_CHECKING, Any

from zros.entity import NodeEntity
from zros.graph import EntityKind
from zros.message import deserialize
from zros.qos import QoSProfile, ReliabilityPolicy
from zros.wire import read_header, type_tail

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
    """Owned by a node: switches its clock between system time and /clock."""

    def __init__(self, node: 'Node') -> None:
        self._node = node
        self._subscription: _ClockSubscription | None = None

    @property
    def enabled(self) -> bool:
        return self._subscription is not None

    def enable(self) -> None:
        """Simulated time from now on; it reads 0 until the first /clock sample (as in ROS 2)."""
        if self._subscription is not None:
            return
        clock = self._node.get_clock()
        clock._add_listener(self._wake_executor)
        clock._set_ros_time_override(0)
        self._subscription = self._node._add(_ClockSubscription(self._node, self))

    def disable(self) -> None:
        if self._subscription is None:
            return
        self._node._destroy_entity(self._subscription)
        self._subscription = None
        clock = self._node.get_clock()
        clock._remove_listener(self._wake_executor)
        clock._set_ros_time_override(None)
        self._wake_executor()

    def _set(self, nanoseconds: int) -> None:
        if self._subscription is not None:
            self._node.get_clock()._set_ros_time_override(nanoseconds)

    def _wake_executor(self) -> None:
        executor = self._node._executor
        if executor is not None:
            executor.wake()
