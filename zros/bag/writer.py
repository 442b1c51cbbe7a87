"""Writing a recording: one MCAP file (chunked, zstd) plus ros2-style metadata.yaml.

The writer is not thread-safe: the recorder calls it from one thread (its executor's). It
keeps per-topic counts and time bounds itself so that `close()` can write metadata.yaml
without reading the file back. `close()` is what makes the MCAP file complete (the summary
and footer), so the recorder calls it on Ctrl-C and SIGTERM too.
"""
from __future__ import annotations

import os
import time
from pathlib import Path
from typing import Any

from zros.bag.definition import MESSAGE_ENCODING, PROFILE, SCHEMA_ENCODING, message_definition
from zros.bag.errors import BagError
from zros.bag.rosbag2 import qos_profiles, qos_yaml

__all__ = ['BagWriter', 'default_bag_name']


def default_bag_name(now: float | None = None) -> str:
    """ros2 bag record's default output name: rosbag2_YYYY_MM_DD-HH_MM_SS."""
    return time.strftime('rosbag2_%Y_%m_%d-%H_%M_%S', time.localtime(now))


class _Topic:
    __slots__ = ('channel_id', 'name', 'type', 'type_hash', 'qos', 'count', 'sequence')

    def __init__(self, channel_id: int, name: str, type_name: str, type_hash: str, qos: str) -> None:
        self.channel_id, self.name, self.type, self.type_hash, self.qos = channel_id, name, type_name, type_hash, qos
        self.count = 0
        self.sequence = 0


class BagWriter:
    """Writes `<directory>/<directory name>_0.mcap` and `<directory>/metadata.yaml`.

    Args:
        directory: the bag directory; it must not exist yet (as with ros2 bag record).
        chunk_size: bytes buffered per MCAP chunk before it is compressed and written.
    Raises:
        BagError: the directory exists or cannot be created.
    """

    encoding = MESSAGE_ENCODING

    def __init__(self, directory: str | os.PathLike[str], *, chunk_size: int = 1 << 20) -> None:
        from mcap.writer import CompressionType, Writer

        from zros import __version__
        self.directory = Path(directory)
        if self.directory.exists():
            raise BagError(f"output folder '{self.directory}' already exists")
        try:
            self.directory.mkdir(parents=True)
        except OSError as exc:
            raise BagError(f"cannot create output folder '{self.directory}': {exc.strerror}") from None
        self.path = self.directory / f'{self.directory.name}_0.mcap'
        self._stream = open(self.path, 'wb')
        self._writer = Writer(self._stream, chunk_size=chunk_size, compression=CompressionType.ZSTD)
        self._writer.start(profile=PROFILE, library=f'zros {__version__}')
        self._schemas: dict[str, int] = {}
        self._topics: dict[str, _Topic] = {}
        self._start: int | None = None
        self._end: int | None = None
        self._closed = False

    @property
    def topics(self) -> dict[str, _Topic]:
        return self._topics

    @property
    def message_count(self) -> int:
        return sum(t.count for t in self._topics.values())

    def add_topic(self, name: str, type_name: str, *, type_hash: str = '', qos: str = '') -> None:
        """Declare a topic (an MCAP channel with its type's full definition as schema)."""
        if name in self._topics:
            return
        schema_id = self._schemas.get(type_name)
        if schema_id is None:
            schema_id = self._writer.register_schema(type_name, SCHEMA_ENCODING,
                                                     message_definition(type_name).encode())
            self._schemas[type_name] = schema_id
        metadata = {'type_hash': type_hash, 'offered_qos_profiles': qos_yaml(qos)}
        channel_id = self._writer.register_channel(name, MESSAGE_ENCODING, schema_id, metadata)
        self._topics[name] = _Topic(channel_id, name, type_name, type_hash, qos)

    def write(self, topic: str, payload: bytes, *, log_time: int, publish_time: int | None = None) -> None:
        """Append one message (`payload` exactly as received) of a topic added before."""
        entry = self._topics[topic]
        entry.count += 1
        entry.sequence += 1
        self._writer.add_message(entry.channel_id, log_time=log_time, data=payload,
                                 publish_time=publish_time or log_time, sequence=entry.sequence & 0xFFFFFFFF)
        if self._start is None or log_time < self._start:
            self._start = log_time
        if self._end is None or log_time > self._end:
            self._end = log_time

    def close(self) -> None:
        """Finish the MCAP file (summary, footer) and write metadata.yaml. Idempotent."""
        if self._closed:
            return
        self._closed = True
        try:
            self._writer.finish()
        finally:
            self._stream.close()
        self._write_metadata()

    def __enter__(self) -> 'BagWriter':
        return self

    def __exit__(self, *exc: Any) -> None:
        self.close()

    def _write_metadata(self) -> None:
        """metadata.yaml in rosbag2's layout (version 9), for tools that look for it."""
        import yaml
        start = self._start or 0
        duration = (self._end - self._start) if self._start is not None else 0
        count = self.message_count
        info = {'rosbag2_bagfile_information': {
            'version': 9,
            'storage_identifier': 'mcap',
            'duration': {'nanoseconds': duration},
            'starting_time': {'nanoseconds_since_epoch': start},
            'message_count': count,
            'topics_with_message_count': [
                {'topic_metadata': {'name': t.name, 'type': t.type, 'serialization_format': MESSAGE_ENCODING,
                                    'offered_qos_profiles': qos_profiles(t.qos),
                                    'type_description_hash': t.type_hash},
                 'message_count': t.count}
                for t in self._topics.values()],
            'compression_format': '',
            'compression_mode': '',
            'relative_file_paths': [self.path.name],
            'files': [{'path': self.path.name, 'starting_time': {'nanoseconds_since_epoch': start},
                       'duration': {'nanoseconds': duration}, 'message_count': count}],
            'custom_data': {},
            'ros_distro': 'zros',
        }}
        with open(self.directory / 'metadata.yaml', 'w') as handle:
            yaml.safe_dump(info, handle, sort_keys=False)
