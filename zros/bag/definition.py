"""Message definitions as MCAP schemas: ROS 2's concatenated `ros2msg` text.

The root type's `.msg` text comes first; each type it uses, directly or not, follows once,
after a line of 80 `=` and a `MSG: pkg/Name` line, which is how rosbag2 writes its MCAP
schemas and what Foxglove, PlotJuggler and the `mcap` CLI parse.
"""
from __future__ import annotations

__all__ = ['message_definition', 'MESSAGE_ENCODING', 'SCHEMA_ENCODING', 'PROFILE']

#: MCAP channel message encoding of zros payloads (docs/protocol.md: one MessagePack map).
MESSAGE_ENCODING = 'msgpack'
#: MCAP schema encoding: ROS 2 .msg text with nested definitions appended.
SCHEMA_ENCODING = 'ros2msg'
#: MCAP header profile. Not "ros2": that profile promises CDR payloads.
PROFILE = 'zros'

_SEPARATOR = '=' * 80


def _short(full_name: str) -> str:
    """'std_msgs/msg/Header' -> 'std_msgs/Header' (the name rosbag2 writes after `MSG:`)."""
    parts = full_name.split('/')
    return f'{parts[0]}/{parts[-1]}' if len(parts) == 3 else full_name


def message_definition(type_name: str) -> str:
    """The full definition text of message type `type_name` ('pkg/msg/Name').

    Raises:
        InterfaceNotFoundError: the type (or a type it uses) is not on the interface path.
    """
    from zros.typesupport import get_message
    root = get_message(type_name)._SPEC
    seen: list[str] = []

    def visit(spec) -> None:
        for dependency in spec.dependencies():
            if dependency not in seen:
                seen.append(dependency)
                visit(get_message(dependency)._SPEC)
    visit(root)
    parts = [root.text.rstrip('\n')]
    for dependency in seen:
        text = get_message(dependency)._SPEC.text.rstrip('\n')
        parts.append(f'{_SEPARATOR}\nMSG: {_short(dependency)}\n{text}')
    return '\n'.join(parts) + '\n'
