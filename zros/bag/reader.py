"""Reading a recording: its summary (for `zros bag info`) and its messages in time order.

A bag is a directory with one `.mcap` file (or the `.mcap` file itself). A file whose
recorder was killed without a chance to finish it (SIGKILL, power loss) has no summary; the
reader then scans it record by record and stops quietly at the first incomplete one, so
everything written before the crash can still be read and played.
"""
from __future__ import annotations

import os
from pathlib import Path
from typing import Iterator, NamedTuple

from zros.bag.errors import BagError

__all__ = ['BagReader', 'TopicInfo', 'BagSummary', 'BagMessage', 'find_mcap']


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
                topics.append(TopicInfo(channel.topic, schema.name if schema else '',
                                        stats.channel_message_counts.get(channel_id, 0),
                                        channel.message_encoding, channel.metadata.get('type_hash', ''),
                                        channel.metadata.get('offered_qos_profiles', '')))
            count = stats.message_count
            return BagSummary([self.path.name], size, 'mcap', stats.message_start_time if count else 0,
                              stats.message_end_time if count else 0, count, topics, True)
        return self._scan_summary(size)

    def _scan_summary(self, size: int) -> BagSummary:
        counts: dict[str, int] = {}
        types: dict[str, tuple[str, str, str, str]] = {}
        start = end = None
        total = 0
        for message in self._scan():
            total += 1
            counts[message.topic] = counts.get(message.topic, 0) + 1
            start = message.log_time if start is None else min(start, message.log_time)
            end = message.log_time if end is None else max(end, message.log_time)
        for topic, info in self._scanned_channels.items():
            types[topic] = info
        topics = [TopicInfo(name, types[name][0], counts.get(name, 0), types[name][1], types[name][2], types[name][3])
                  for name in sorted(types)]
        return BagSummary([self.path.name], size, 'mcap', start or 0, end or 0, total, topics, False)

    # -- messages -----------------------------------------------------------------------------
    def messages(self, topics: list[str] | None = None, *, start_time: int | None = None) -> Iterator[BagMessage]:
        """Every message (of `topics`, from `start_time` on) in log-time order."""
        from mcap.exceptions import McapError
        from mcap.reader import make_reader
        with open(self.path, 'rb') as stream:
            reader = make_reader(stream)
            try:
                summary = reader.get_summary()
            except (McapError, OSError, ValueError, EOFError):
                summary = None
            if summary is not None:
                for schema, channel, message in reader.iter_messages(topics=topics, start_time=start_time,
                                                                     log_time_order=True):
                    yield BagMessage(channel.topic, schema.name if schema else '', message.data,
                                     message.log_time, message.publish_time)
                return
        wanted = set(topics) if topics else None
        scanned = [m for m in self._scan() if (wanted is None or m.topic in wanted)
                   and (start_time is None or m.log_time >= start_time)]
        scanned.sort(key=lambda m: m.log_time)
        yield from scanned

    def _scan(self) -> Iterator[BagMessage]:
        """Messages in file order, read record by record; stops at the first broken record."""
        from mcap.records import Channel, Message, Schema
        from mcap.stream_reader import StreamReader
        self._scanned_channels: dict[str, tuple[str, str, str, str]] = {}
        schemas: dict[int, str] = {}
        channels: dict[int, tuple[str, str]] = {}
        with open(self.path, 'rb') as stream:
            records = StreamReader(stream, skip_magic=False, emit_chunks=False).records
            while True:
                try:
                    record = next(records)
                except StopIteration:
                    return
                except Exception:  # noqa: BLE001 - a truncated tail: everything before it is good
                    return
                if isinstance(record, Schema):
                    schemas[record.id] = record.name
                elif isinstance(record, Channel):
                    type_name = schemas.get(record.schema_id, '')
                    channels[record.id] = (record.topic, type_name)
                    self._scanned_channels[record.topic] = (type_name, record.message_encoding,
                                                            record.metadata.get('type_hash', ''),
                                                            record.metadata.get('offered_qos_profiles', ''))
                elif isinstance(record, Message) and record.channel_id in channels:
                    topic, type_name = channels[record.channel_id]
                    yield BagMessage(topic, type_name, record.data, record.log_time, record.publish_time)

    def channel_info(self) -> dict[str, TopicInfo]:
        return {t.name: t for t in self.summary().topics}
