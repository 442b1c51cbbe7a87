"""Recording and playing back topics: `zros bag record|play|info|convert`.

A recording is a directory (ros2 bag's layout) holding one `.mcap` file and a `metadata.yaml`.
By default it is a rosbag2 bag: CDR payloads (`zros.bag.cdr`) under `ros2msg` schemas, what
ros2 bag, Foxglove, PlotJuggler, `rosbags` and `mcap_ros2` read (`zros.bag.rosbag2`). With
`--format msgpack` it is zros's own: each topic's MCAP channel has message encoding `msgpack`
(the zros payload, stored byte for byte as it arrived, no re-encoding) under the same schemas.
Log time is the receive time, publish time the sender's source timestamp. rosbag2 bags from
ROS 2 (MCAP or SQLite 3) are read and played too. See docs/bag.md.

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
