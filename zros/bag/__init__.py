"""Recording and playing back topics: `zros bag record|play|info|convert`.

A zros recording is a directory (ros2 bag's layout) holding one `.mcap` file and a small
`metadata.yaml`. Each topic is one MCAP channel whose message encoding is `msgpack` (the zros
payload, stored byte for byte as it arrived) and whose schema is the message definition in
ROS 2's concatenated `ros2msg` form. Log time is the receive time, publish time the sender's
source timestamp. ROS tools cannot decode MessagePack, so `--format cdr` writes a rosbag2 bag
instead (`zros.bag.rosbag2`, CDR from `zros.bag.cdr`), and rosbag2 bags from ROS 2 (MCAP or
SQLite 3) are read and played. See docs/bag.md.

Only `zros.bag.definition` is light; the writers and readers import `mcap` / `rosbags` when used.
"""
from __future__ import annotations

__all__ = ['BagError', 'BagWriter', 'BagReader', 'TopicInfo', 'BagSummary', 'message_definition',
           'Recorder', 'Player', 'MESSAGE_ENCODING', 'SCHEMA_ENCODING']

from zros.bag.errors import BagError
from zros.bag.definition import MESSAGE_ENCODING, SCHEMA_ENCODING, message_definition


def __getattr__(name: str):
    # The writer, reader, recorder and player pull in mcap (and zstandard): load them on use.
    if name in ('BagWriter',):
        from zros.bag.writer import BagWriter
        return BagWriter
    if name in ('BagReader', 'TopicInfo', 'BagSummary'):
        from zros.bag import reader
        return getattr(reader, name)
    if name == 'Recorder':
        from zros.bag.recorder import Recorder
        return Recorder
    if name == 'Player':
        from zros.bag.player import Player
        return Player
    raise AttributeError(f"module 'zros.bag' has no attribute '{name}'")
