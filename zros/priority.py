"""Zenoh transport priority and express per topic: small urgent messages overtake big ones.

Across a slow link (a robot on Wi-Fi at a few Mbit/s) one 150 kB map or a 1 MB image takes
most of a second to send. Zenoh keeps one transmission queue per priority and always sends the
highest non-empty one first, at batch boundaries, so a `cmd_vel` at REAL_TIME does not wait
behind a map at DATA_LOW; `express` sends a message at once instead of waiting for a batch to
fill. ROS 2 has no QoS policy for either (rmw_zenoh leaves them to Zenoh's own `qos/publication`
config, which zros honours too: it overrides what is chosen here), so zros picks them per topic:

- built-in defaults where it matters: velocity commands (a topic whose last name is `cmd_vel`
  or starts with `cmd_vel_`) at `real_time` + express; TF (`tf2_msgs/msg/TFMessage`) at
  `interactive_high` + express; grids, images and point clouds at `data_low`; everything else
  at Zenoh's default, `data`.
- `ZROS_TOPIC_PRIORITY`, a comma-separated list of `TOPIC=PRIORITY[:express]` rules (the shape
  of zenoh-bridge-ros2dds's `pub_priorities`), which replace the defaults for the topics they
  match: `/cmd_vel=real_time:express,/camera/*=background`. TOPIC is a shell-style pattern on
  the absolute topic name (`*` also matches `/`); PRIORITY is a Zenoh priority name or its
  number, 1 (real_time) to 7 (background). The first matching rule wins.

Priority and express change only how a sample travels: keys, payloads, QoS tokens and the graph
are the same, and any subscriber (zros, rmw_zenoh, a plain Zenoh client) receives it as before.
Pure data: the publisher turns the chosen name into `zenoh.Priority`.
"""
from __future__ import annotations

import fnmatch
import os
from functools import lru_cache
from typing import NamedTuple

from zros.errors import ZrosError

__all__ = ['PRIORITIES', 'TransportPriority', 'DEFAULT', 'parse_topic_priorities', 'default_priority',
           'transport_priority', 'ENV']

#: Zenoh's priorities, highest first; a rule may give the name or its number (index + 1).
PRIORITIES = ('real_time', 'interactive_high', 'interactive_low', 'data_high', 'data', 'data_low', 'background')
ENV = 'ZROS_TOPIC_PRIORITY'


class TransportPriority(NamedTuple):
    """How a topic's samples travel: a name of PRIORITIES, and whether they skip batching."""
    priority: str = 'data'
    express: bool = False


DEFAULT = TransportPriority()
_COMMAND = TransportPriority('real_time', True)
_TF = TransportPriority('interactive_high', True)
_BULK = TransportPriority('data_low', False)
#: Message types big enough to hold a slow link for a while (a grid, a frame, a cloud).
_BULK_TYPES = frozenset({
    'nav_msgs/msg/OccupancyGrid', 'map_msgs/msg/OccupancyGridUpdate', 'nav2_msgs/msg/Costmap',
    'nav2_msgs/msg/VoxelGrid', 'sensor_msgs/msg/Image', 'sensor_msgs/msg/CompressedImage',
    'sensor_msgs/msg/PointCloud2', 'sensor_msgs/msg/PointCloud'})

Rules = tuple[tuple[str, TransportPriority], ...]


def default_priority(topic: str, type_name: str) -> TransportPriority:
    """zros's built-in choice for `topic` (an absolute name) carrying `type_name`."""
    last = topic.rsplit('/', 1)[-1]
    if last == 'cmd_vel' or last.startswith('cmd_vel_'):
        return _COMMAND
    if type_name == 'tf2_msgs/msg/TFMessage':
        return _TF
    if type_name in _BULK_TYPES:
        return _BULK
    return DEFAULT


def _priority_name(text: str, rule: str) -> str:
    word = text.strip().lower().replace('-', '_')
    if word.isdigit() and 1 <= int(word) <= len(PRIORITIES):
        return PRIORITIES[int(word) - 1]
    if word in PRIORITIES:
        return word
    raise ZrosError(f"{ENV}: '{rule}': unknown priority '{text.strip()}'; expected one of "
                    f"{', '.join(PRIORITIES)} or 1-7")


@lru_cache(maxsize=8)
def parse_topic_priorities(text: str) -> Rules:
    """The rules of a `ZROS_TOPIC_PRIORITY` value, in order; ZrosError (one line) if malformed."""
    rules: list[tuple[str, TransportPriority]] = []
    for rule in filter(None, (part.strip() for part in text.split(','))):
        pattern, sep, setting = rule.partition('=')
        pattern = pattern.strip()
        if not sep or not pattern.startswith('/'):
            raise ZrosError(f"{ENV}: '{rule}' is not TOPIC=PRIORITY[:express] with an absolute topic, "
                            "e.g. /cmd_vel=real_time:express")
        name, colon, flag = setting.partition(':')
        if colon and flag.strip().lower() != 'express':
            raise ZrosError(f"{ENV}: '{rule}': unknown flag '{flag.strip()}'; the only flag is ':express'")
        rules.append((pattern, TransportPriority(_priority_name(name, rule), bool(colon))))
    return tuple(rules)


def transport_priority(topic: str, type_name: str, rules: Rules | None = None) -> TransportPriority:
    """The priority and express flag for a publisher on `topic` (absolute) of `type_name`.

    Args:
        topic: the fully qualified topic name, e.g. `/robot1/cmd_vel`.
        type_name: the message type, e.g. `geometry_msgs/msg/Twist`.
        rules: parsed rules; by default `ZROS_TOPIC_PRIORITY`'s (read at each call, parsed once).
    Raises:
        ZrosError: `ZROS_TOPIC_PRIORITY` is malformed.
    """
    if rules is None:
        rules = parse_topic_priorities(os.environ.get(ENV, ''))
    for pattern, setting in rules:
        if fnmatch.fnmatchcase(topic, pattern):
            return setting
    return default_priority(topic, type_name)
