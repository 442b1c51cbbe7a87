"""parameter_bridge: ros_gz_bridge's relay between Gazebo Sim's topics and ROS topics.

    zros run ros_gz_bridge parameter_bridge --ros-args -p config_file:=configs/bridge.yaml
    zros run ros_gz_bridge parameter_bridge /scan@sensor_msgs/msg/LaserScan[gz.msgs.LaserScan \\
        /cmd_vel@geometry_msgs/msg/Twist]gz.msgs.Twist /clock@rosgraph_msgs/msg/Clock[gz.msgs.Clock

In Gazebo Sim a robot's lidar publishes on Gazebo Transport, and `/scan` exists for ROS only
when a bridge relays it; zros's simulator does the same on its hidden Gazebo side
(zros.sim.gz_topics), and this node is the relay: for each entry (zros.sim.gz_bridge: the YAML
`config_file` and the command-line forms) it subscribes one side and republishes on the other,
as serialized bytes (no decoding) when both sides carry the same type, converting otherwise
(a TwistStamped on ROS's side, a Twist on Gazebo's). Parameters: `config_file`,
`expand_gz_topic_names` (Gazebo topic names relative to the node's namespace, as ROS names are;
off by default, as in ros_gz_bridge), `subscription_heartbeat` [ms] (how often a lazy entry looks
for subscribers: it relays only while the other side has one). A bad configuration is one line
and exit 1.

A BIDIRECTIONAL entry relays both ways; the node skips the echo of its own publications (by
their bytes), as ros_gz_bridge skips its own messages.
"""
from __future__ import annotations

import collections
import sys
from pathlib import Path
from typing import Any, Callable

import zros
from zros.errors import CliError
from zros.arguments import remove_ros_args
from zros.executors import ExternalShutdownException
from zros.message import encoder
from zros.node import Node
from zros.qos import QoSProfile
from zros.sim.gz_bridge import BridgeConfigError, BridgeEntry, Direction, gz_side_type, parse_bridge_argument, \
    parse_bridge_config
from zros.sim.gz_topics import GZ_PREFIX, gz_key
from zros.typesupport import get_message

__all__ = ['BridgeNode', 'main', 'load_entries']

#: (from type, to type) -> conversion of a message, where the two sides carry different types.
_CONVERSIONS: dict[tuple[str, str], Callable[[Any, type], Any]] = {
    ('geometry_msgs/msg/TwistStamped', 'geometry_msgs/msg/Twist'): lambda msg, to: msg.twist,
    ('geometry_msgs/msg/Twist', 'geometry_msgs/msg/TwistStamped'): lambda msg, to: to(twist=msg),
}
_ECHO_MEMORY = 64      # publications per topic whose echo a bidirectional entry remembers


def load_entries(config_file: str, arguments: list[str]) -> list[BridgeEntry]:
    """The entries of a config file and of command-line arguments; CliError (one line) if bad."""
    try:
        entries = [parse_bridge_argument(argument) for argument in arguments]
        if config_file:
            try:
                text = Path(config_file).read_text(encoding='utf-8')
            except (OSError, UnicodeDecodeError) as exc:
                raise CliError(f'cannot read config_file {config_file}: '
                               f'{exc.strerror if isinstance(exc, OSError) else exc}') from None
            entries += parse_bridge_config(text, config_file)
    except BridgeConfigError as exc:
        raise CliError(str(exc)) from None
    for entry in entries:
        types = (entry.ros_type, gz_side_type(entry))
        if types[0] != types[1] and (types not in _CONVERSIONS or types[::-1] not in _CONVERSIONS):
            raise CliError(f'bridge {entry.ros_topic}: zros carries {entry.gz_type} as {types[1]} and cannot '
                           f'convert it to {types[0]}')
    return entries


class _Relay:
    """One direction of one entry: a subscription on one side, a publisher on the other."""

    def __init__(self, node: Node, source: tuple[str, str], target: tuple[str, str], entry: BridgeEntry,
                 echoes: dict[str, collections.Counter]) -> None:
        (self.source_type, self.source), (self.target_type, self.target) = source, target
        self.node, self.entry, self._echoes = node, entry, echoes
        self._source_cls, self._target_cls = get_message(self.source_type), get_message(self.target_type)
        self._convert = _CONVERSIONS.get((self.source_type, self.target_type))
        self._encode = encoder(self._target_cls)     # the wire bytes, to know a publication's echo
        self.publisher = node.create_publisher(self._target_cls, self.target, QoSProfile(depth=entry.publisher_queue))
        self.subscription = None
        if not entry.lazy:
            self.connect()

    def connect(self) -> None:
        self.subscription = self.node.create_subscription(
            self._source_cls, self.source, self.relay, QoSProfile(depth=self.entry.subscriber_queue),
            raw=self._convert is None)

    def disconnect(self) -> None:
        self.node.destroy_subscription(self.subscription)
        self.subscription = None

    def heartbeat(self) -> None:
        """Lazy: subscribe the source only while the target side has a subscriber."""
        wanted = self.publisher.get_subscription_count() > 0
        if wanted and self.subscription is None:
            self.connect()
        elif not wanted and self.subscription is not None:
            self.disconnect()

    def relay(self, msg: Any) -> None:
        pending = self._echoes.get(self.source)
        if pending is not None and isinstance(msg, bytes) and pending[msg]:
            pending[msg] -= 1      # our own publication on this side, coming back: not relayed again
            return
        out = msg if self._convert is None else self._convert(msg, self._target_cls)
        sent = self._echoes.get(self.target)
        if sent is not None:
            if sum(sent.values()) >= _ECHO_MEMORY:
                sent.clear()
            sent[out if isinstance(out, bytes) else bytes(self._encode(out))] += 1
        self.publisher.publish(out)


class BridgeNode(Node):
    """The bridge: one or two relays per entry."""

    def __init__(self, arguments: list[str], **kwargs: Any) -> None:
        super().__init__('ros_gz_bridge', **kwargs)
        config_file = str(self.declare_parameter('config_file', '').value)
        expand = bool(self.declare_parameter('expand_gz_topic_names', False).value)
        heartbeat_ms = float(self.declare_parameter('subscription_heartbeat', 1000).value)
        entries = load_entries(config_file, arguments)
        if not entries:
            raise CliError('no bridges: give config_file:=FILE or topic@ros_type[gz_type arguments')
        namespace = self.get_namespace() if expand else ''
        echoes: dict[str, collections.Counter] = {}
        self.relays: list[_Relay] = []
        for entry in entries:
            ros = (entry.ros_type, entry.ros_topic)
            gz = (gz_side_type(entry), gz_key(entry.gz_topic, namespace))
            if entry.direction is Direction.BIDIRECTIONAL:
                for topic in (self.resolve_topic_name(entry.ros_topic), gz[1]):
                    echoes.setdefault(topic, collections.Counter())
                ros = (entry.ros_type, self.resolve_topic_name(entry.ros_topic))
            if entry.direction is not Direction.ROS_TO_GZ:
                self.relays.append(_Relay(self, gz, ros, entry, echoes))
            if entry.direction is not Direction.GZ_TO_ROS:
                self.relays.append(_Relay(self, ros, gz, entry, echoes))
            self.get_logger().info(f'Creating {entry.direction.value} bridge [{entry.ros_topic} ({entry.ros_type})'
                                   f' <-> {gz[1].removeprefix(GZ_PREFIX)} ({entry.gz_type})]'
                                   + (' (Lazy)' if entry.lazy else ''))
        if any(entry.lazy for entry in entries):
            self.create_timer(heartbeat_ms / 1000.0, lambda: [r.heartbeat() for r in self.relays if r.entry.lazy])


def main(args: list[str] | None = None) -> None:
    argv = list(sys.argv if args is None else args)
    try:
        with zros.init(args=argv):
            zros.spin(BridgeNode(remove_ros_args(argv)[1:]))
    except (KeyboardInterrupt, ExternalShutdownException):
        pass


if __name__ == '__main__':
    main(sys.argv)
