"""What foxglove_bridge tells a Foxglove client about the zros graph: schemas, names, filters.

Pure functions, no sockets and no sessions, so they are tested fast and the bridge stays a
thin loop. A channel's schema is the `ros2msg` definition rosbag2 writes (zros.bag.definition)
and its encoding CDR (zros.bag.cdr), the pair Foxglove decodes for ROS 2; parameters are named
`/node.param` and whitelists are lists of regular expressions that must match a whole name, as
in ROS's foxglove_bridge.
"""
from __future__ import annotations

import re
from typing import Iterable, NamedTuple

from zros.bag.cdr import CDR_ENCODING
from zros.bag.definition import SCHEMA_ENCODING, message_definition

__all__ = ['ChannelSchema', 'channel_schema', 'service_schemas', 'compile_whitelist', 'allowed',
           'is_hidden', 'parameter_name', 'split_parameter_name', 'full_type_name', 'CDR_ENCODING',
           'SCHEMA_ENCODING']


class ChannelSchema(NamedTuple):
    """One message schema as the Foxglove protocol carries it."""
    name: str        # 'pkg/msg/Name'
    encoding: str    # 'ros2msg'
    data: bytes      # the concatenated definition text, UTF-8


def channel_schema(type_name: str) -> ChannelSchema:
    """The schema a topic of `type_name` is advertised with.

    Raises:
        InterfaceNotFoundError: zros does not know the type.
    """
    return ChannelSchema(type_name, SCHEMA_ENCODING, message_definition(type_name).encode())


def service_schemas(service_type: str) -> tuple[ChannelSchema, ChannelSchema]:
    """(request, response) schemas of service type 'pkg/srv/Name', named 'pkg/srv/Name_Request'
    and 'pkg/srv/Name_Response' as rosbag2 and foxglove_bridge name them."""
    return channel_schema(f'{service_type}_Request'), channel_schema(f'{service_type}_Response')


def full_type_name(name: str) -> str:
    """'geometry_msgs/PoseStamped' (how Foxglove's panels name a type) -> 'geometry_msgs/msg/PoseStamped'."""
    parts = name.strip('/').split('/')
    return f'{parts[0]}/msg/{parts[1]}' if len(parts) == 2 else '/'.join(parts)


def compile_whitelist(patterns: Iterable[str]) -> list[re.Pattern[str]]:
    """Regular expressions from a `*_whitelist` parameter.

    Raises:
        ValueError: a pattern is not a valid regular expression (named in the message).
    """
    compiled = []
    for pattern in patterns:
        try:
            compiled.append(re.compile(pattern))
        except re.error as exc:
            raise ValueError(f"invalid whitelist pattern '{pattern}': {exc}") from None
    return compiled


def allowed(name: str, whitelist: list[re.Pattern[str]]) -> bool:
    """True when one pattern matches all of `name` (ROS's foxglove_bridge uses regex_match)."""
    return any(pattern.fullmatch(name) for pattern in whitelist)


def is_hidden(name: str) -> bool:
    """A hidden topic or service has a name part starting with '_' (ros2 topic list hides them)."""
    return any(part.startswith('_') for part in name.split('/') if part)


def parameter_name(node_fqn: str, param: str) -> str:
    """The name a client sees: '/turtlesim' + 'background_r' -> '/turtlesim.background_r'."""
    return f'{node_fqn}.{param}'


def split_parameter_name(name: str) -> tuple[str, str]:
    """'/ns/node.param.sub' -> ('/ns/node', 'param.sub').

    Raises:
        ValueError: the name has no node part or no parameter part.
    """
    node, dot, param = name.partition('.')
    if not dot or not param or not node.startswith('/') or node == '/':
        raise ValueError(f"parameter name '{name}' is not '/node.parameter'")
    return node, param
