"""Reading a recording: its summary (for `zros bag info`) and its messages in time order.

`open_bag(path)` picks the reader. A bag is a directory with one `.mcap` file (or the `.mcap`
file itself), read here whatever its message encoding (zros's `msgpack`, ROS 2's `cdr`). A file
whose recorder was killed without a chance to finish it (SIGKILL, power loss) has no summary;
the reader then scans it record by record and stops at the first incomplete one, so everything
written before the crash can still be read and played. A file from which not one message can
be read that way is corrupt, and says so. SQLite 3 (`.db3`) and split rosbag2 bags go to
`zros.bag.rosbag2.Rosbag2Reader`.
"""
from __future__ import annotations

import os
import re
from pathlib import Path
from typing import Any, Iterator, NamedTuple

from zros.bag.errors import BagError

_QOS_TOKEN = re.compile(r'^[RB]:[VT]:(L\d+|A)$')

__all__ = ['BagReader', 'TopicInfo', 'BagSummary', 'BagMessage', 'find_mcap', 'open_bag']


class TopicInfo(NamedTuple):
    name: str
    type: str
    count: int
    encoding: str
    type_hash: str = ''
    qos: str = ''


class BagSummary(NamedTuple):
    files: list[str]
    size: int                 # bytes, all files
    storage_id: str
    start: int                # ns since the epoch (log time of the first message)
    end: int
    message_count: int
    topics: list[TopicInfo]
    complete: bool            # False when the file had no summary (recorder killed)


class BagMessage(NamedTuple):
    topic: str
    type: str
    data: bytes
    log_time: int
    publish_time: int


def open_bag(path: str | os.PathLike[str]) -> Any:
    """The reader for the bag at `path`: `BagReader` for one MCAP file, `Rosbag2Reader` for a
    `.db3` file or a rosbag2 directory holding `.db3` files or several MCAP files.

    Raises:
        BagError: nothing readable is there.
    """
    path = Path(path)
    if path.is_dir():
        if any(path.glob('*.db3')) or (len(list(path.glob('*.mcap'))) > 1 and (path / 'metadata.yaml').exists()):
            from zros.bag.rosbag2 import Rosbag2Reader
            return Rosbag2Reader(path)
    elif path.suffix == '.db3' and path.exists():
        from zros.bag.rosbag2 import Rosbag2Reader
        return Rosbag2Reader(path)
    return BagReader(path)


def find_mcap(path: str | os.PathLike[str]) -> Path:
    """The .mcap file of a bag given as a directory or as the file itself."""
    path = Path(path)
    if path.is_dir():
        files = sorted(path.glob('*.mcap'))
        if not files:
            raise BagError(f"no .mcap file in '{path}'")
        return files[0]
    if not path.exists():
        raise BagError(f"bag '{path}' does not exist")
    return path


class BagReader:
    """Opens a bag for reading. Raises BagError when it is missing or not an MCAP file."""

    def __init__(self, path: str | os.PathLike[str]) -> None:
        self.path = find_mcap(path)
        with open(self.path, 'rb') as stream:
            if stream.read(8) != b'\x89MCAP0\r\n':
                raise BagError(f"'{self.path}' is not an MCAP file")

    # -- summary ------------------------------------------------------------------------------
    def summary(self) -> BagSummary:
        from mcap.exceptions import McapError
        from mcap.reader import make_reader
        size = self.path.stat().st_size
        summary = None
        with open(self.path, 'rb') as stream:
            try:
                summary = make_reader(stream).get_summary()
            except (McapError, OSError, ValueError, EOFError):
                summary = None
        if summary is not None and summary.statistics is not None:
            stats = summary.statistics
            topics = []
            for channel_id, channel in sorted(summary.channels.items(), key=lambda kv: kv[1].topic):
                schema = summary.schemas.get(channel.schema_id)
                topics.append(_topic_info(channel, schema.name if schema else '',
                                          stats.channel_message_counts.get(channel_id, 0)))
            count = stats.message_count
            return BagSummary([self.path.name], size, 'mcap', stats.message_start_time if count else 0,
                              stats.message_end_time if count else 0, count, topics, True)
        return self._scan_summary(size)

    def _scan_summary(self, size: int) -> BagSummary:
        counts: dict[str, int] = {}
        start = end = None
        total = 0
        for message in self._scan():
            total += 1
            counts[message.topic] = counts.get(message.topic, 0) + 1
            start = message.log_time if start is None else min(start, message.log_time)
            end = message.log_time if end is None else max(end, message.log_time)
        topics = [_topic_info(channel, type_name, counts.get(name, 0))
                  for name, (channel, type_name) in sorted(self._scanned_channels.items())]
        return BagSummary([self.path.name], size, 'mcap', start or 0, end or 0, total, topics, False)

    # -- messages -----------------------------------------------------------------------------
    def messages(self, topics: list[str] | None = None, *, start_time: int | None = None) -> Iterator[BagMessage]:
        """Every message (of `topics`, from `start_time` on) in log-time order.

        Raises:
            BagError: a chunk is corrupt (the messages before it have been yielded).
        """
        from mcap.exceptions import McapError
        from mcap.reader import make_reader
        with open(self.path, 'rb') as stream:
            reader = make_reader(stream)
            try:
                summary = reader.get_summary()
            except (McapError, OSError, ValueError, EOFError):
                summary = None
            if summary is not None:
                try:
                    for schema, channel, message in reader.iter_messages(topics=topics, start_time=start_time,
                                                                         log_time_order=True):
                        yield BagMessage(channel.topic, schema.name if schema else '', message.data,
                                         message.log_time, message.publish_time)
                except Exception as exc:  # noqa: BLE001 - mcap, zstd and lz4 raise their own types
                    raise BagError(f"'{self.path}' is corrupt: {type(exc).__name__}: {exc}") from None
                return
        wanted = set(topics) if topics else None
        scanned = [m for m in self._scan() if (wanted is None or m.topic in wanted)
                   and (start_time is None or m.log_time >= start_time)]
        scanned.sort(key=lambda m: m.log_time)
        yield from scanned

    def _scan(self) -> Iterator[BagMessage]:
        """Messages in file order, read record by record; stops at the first broken record.

        A broken record after at least one message is a recording cut short (the recorder was
        killed): what came before is good. Broken before any message, the file is corrupt.

        Raises:
            BagError: not one message could be read before the file broke off.
        """
        from mcap.records import Channel, Message, Schema
        from mcap.stream_reader import StreamReader
        self._scanned_channels: dict[str, tuple[Any, str]] = {}
        schemas: dict[int, str] = {}
        channels: dict[int, tuple[str, str]] = {}
        found = 0
        with open(self.path, 'rb') as stream:
            records = StreamReader(stream, skip_magic=False, emit_chunks=False).records
            while True:
                try:
                    record = next(records)
                except StopIteration:
                    return
                except Exception as exc:  # noqa: BLE001 - the mcap reader raises many types on a broken tail
                    if found:
                        return
                    why = str(exc) or type(exc).__name__
                    raise BagError(f"'{self.path}' is corrupt or truncated: no message could be read ({why})") \
                        from None
                if isinstance(record, Schema):
                    schemas[record.id] = record.name
                elif isinstance(record, Channel):
                    type_name = schemas.get(record.schema_id, '')
                    channels[record.id] = (record.topic, type_name)
                    self._scanned_channels[record.topic] = (record, type_name)
                elif isinstance(record, Message) and record.channel_id in channels:
                    found += 1
                    topic, type_name = channels[record.channel_id]
                    yield BagMessage(topic, type_name, record.data, record.log_time, record.publish_time)

    def channel_info(self) -> dict[str, TopicInfo]:
        return {t.name: t for t in self.summary().topics}


def _topic_info(channel: Any, type_name: str, count: int) -> TopicInfo:
    """A channel's TopicInfo. zros writes its own type hash (`type_hash`); rosbag2 writes RIHS01
    (`topic_type_hash`). QoS is kept as a zros token; rosbag2's YAML profiles are converted."""
    metadata = channel.metadata
    qos = metadata.get('offered_qos_profiles', '')
    if qos and not _QOS_TOKEN.match(qos):
        from zros.bag.rosbag2 import qos_token_from_rosbag2
        qos = qos_token_from_rosbag2(qos)
    return TopicInfo(channel.topic, type_name, count, channel.message_encoding,
                     metadata.get('type_hash') or metadata.get('topic_type_hash', ''), qos)
