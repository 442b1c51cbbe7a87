"""What relay, throttle and drop share: a node that copies one topic to another, typed by the graph.

Like ROS 2's topic_tools, the tool is given only topic names: every 0.1 s it looks at the input
topic's publishers, takes their type and QoS (reliable and transient-local only if all of them
are, so that it matches every one), and then publishes the messages it lets through on the
output topic, as the serialized bytes it received (nothing is decoded). With `lazy`, it
subscribes to the input only while someone subscribes to the output, which is what makes a
relay across a Wi-Fi link cost nothing while nobody looks.
"""
from __future__ import annotations

import time
from typing import Any, Protocol

from zros.errors import CliError
from zros.node import Node
from zros.parameter import Parameter
from zros.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from zros.typesupport import get_message

__all__ = ['ToolNode', 'Filter', 'DISCOVERY_PERIOD', 'overrides', 'run']

DISCOVERY_PERIOD = 0.1   # [s] between looks at the input topic's publishers


class Filter(Protocol):
    def accept(self, now: float, nbytes: int) -> bool: ...


def overrides(**values: Any) -> list[Parameter]:
    """The positional command line as parameters (ROS's tools do the same), skipping the unset."""
    return [Parameter(name, value=value) for name, value in values.items() if value is not None]


class ToolNode(Node):
    """A node named `name` copying `input_topic` to `output_topic` (default: input + `suffix`)
    through `make_filter(node)`; `use_wall_clock` picks the filter's clock."""

    def __init__(self, name: str, suffix: str, *, parameter_overrides: list[Parameter], **kwargs: Any) -> None:
        super().__init__(name, parameter_overrides=parameter_overrides, **kwargs)
        self.input_topic = str(self.declare_parameter('input_topic', '').value)
        if not self.input_topic:
            raise CliError(f'{name}: no input topic (give it on the command line or as the input_topic parameter)')
        self.output_topic = str(self.declare_parameter('output_topic', self.input_topic + suffix).value)
        self.lazy = bool(self.declare_parameter('lazy', False).value)
        self._wall = bool(self.declare_parameter('use_wall_clock', False).value)
        self.filter: Filter = self.make_filter()
        self._type = ''
        self._qos: QoSProfile | None = None
        self._pub: Any = None
        self._sub: Any = None
        self.create_timer(DISCOVERY_PERIOD, self._discover)

    def make_filter(self) -> Filter:
        raise NotImplementedError

    def _now(self) -> float:
        return time.monotonic() if self._wall else self.get_clock().now().nanoseconds * 1e-9

    def _source(self) -> tuple[str, QoSProfile] | None:
        """The input's type and a QoS that matches all its publishers (not this node's own)."""
        found = [i for i in self.get_publishers_info_by_topic(self.input_topic)
                 if (i.node_name, i.node_namespace) != (self.get_name(), self.get_namespace())]
        if not found:
            return None
        profiles = [i.qos_profile for i in found]
        reliable = all(p.reliability == ReliabilityPolicy.RELIABLE for p in profiles)
        latched = all(p.durability == DurabilityPolicy.TRANSIENT_LOCAL for p in profiles)
        return found[0].topic_type, QoSProfile(
            depth=10, reliability=ReliabilityPolicy.RELIABLE if reliable else ReliabilityPolicy.BEST_EFFORT,
            durability=DurabilityPolicy.TRANSIENT_LOCAL if latched else DurabilityPolicy.VOLATILE)

    def _discover(self) -> None:
        source = self._source()
        if source is None:
            self._drop_endpoints()       # a new source may bring another type
            return
        if source != (self._type, self._qos) or self._pub is None:
            self._drop_endpoints()
            self._type, self._qos = source
            try:
                self._msg_type = get_message(self._type)
            except Exception as exc:     # an unknown type is reported, and tried again next time
                self.get_logger().warn(f"cannot relay {self.input_topic}: type '{self._type}': {exc}", once=True)
                self._type = ''
                return
            self._pub = self.create_publisher(self._msg_type, self.output_topic, self._qos)
        wanted = not self.lazy or self._pub.get_subscription_count() > 0
        if wanted and self._sub is None:
            self._sub = self.create_subscription(self._msg_type, self.input_topic, self._on_message, self._qos,
                                                 raw=True)
        elif not wanted and self._sub is not None:
            self.destroy_subscription(self._sub)
            self._sub = None

    def _drop_endpoints(self) -> None:
        if self._sub is not None:
            self.destroy_subscription(self._sub)
        if self._pub is not None:
            self.destroy_publisher(self._pub)
        self._sub = self._pub = None
        self._type, self._qos = '', None

    def _on_message(self, data: bytes) -> None:
        if self._pub is not None and self.filter.accept(self._now(), len(data)):
            self._pub.publish(data)


def run(make_node: Any, args: list[str] | None, usage: str) -> None:
    """Parse the positional arguments with `make_node(positional) -> ToolNode` and spin it;
    a missing or malformed argument is a one-line error naming `usage`."""
    import sys

    import zros
    from zros.executors import ExternalShutdownException
    from zros.utilities import remove_ros_args

    argv = sys.argv if args is None else args
    try:
        with zros.init(args=argv):
            try:
                node = make_node(remove_ros_args(args=argv)[1:])
            except (ValueError, IndexError) as exc:
                raise CliError(f'{exc}; usage: {usage}') from None
            zros.spin(node)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
