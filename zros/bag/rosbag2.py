"""Bags in rosbag2's own profile, through the rosbags library: what ROS 2 tools read and write.

- `CdrBagWriter` writes a rosbag2 bag (version 9 metadata.yaml, `cdr` payloads, `ros2msg`
  definitions, RIHS01 type hashes, QoS profiles as rosbag2's YAML) in MCAP or SQLite 3 storage,
  so `ros2 bag`, Foxglove, PlotJuggler, `rosbags` and `mcap_ros2` open it.
- `Rosbag2Reader` reads what ROS 2 recorded in storages zros's own reader does not handle:
  SQLite 3 (`.db3`, the default before Jazzy) and bags split over several files.

Both expose the interface of `zros.bag.writer.BagWriter` / `zros.bag.reader.BagReader`, so the
recorder, player and converter do not care which one they hold. QoS crosses the boundary as a
zros token (`R:V:L10`, docs/protocol.md) on the zros side and as rosbag2 profiles on the other.
"""
from __future__ import annotations

import os
from pathlib import Path
from typing import Any, Iterator

from zros.bag.cdr import CDR_ENCODING, CdrCodec
from zros.bag.errors import BagError
from zros.bag.reader import BagMessage, BagSummary, TopicInfo

__all__ = ['CdrBagWriter', 'Rosbag2Reader', 'qos_token_to_rosbag2', 'qos_token_from_rosbag2', 'qos_profiles',
           'qos_yaml', 'STORAGES']

#: rosbag2 storage ids `--storage` accepts for CDR bags.
STORAGES = ('mcap', 'sqlite3')

# rosbag2 writes "no deadline / lifespan / lease" as the largest rmw_time_t.
_INFINITE = (9223372036, 854775807)


def qos_token_to_rosbag2(token: str) -> Any:
    """A rosbags `Qos` (what rosbag2 stores per topic) from a zros QoS token."""
    from rosbags.interfaces import Qos, QosDurability, QosHistory, QosLiveliness, QosReliability, QosTime

    from zros.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy
    profile = QoSProfile.from_token(token)
    infinite = QosTime(*_INFINITE)
    return Qos(QosHistory.KEEP_ALL if profile.history == HistoryPolicy.KEEP_ALL else QosHistory.KEEP_LAST,
               profile.depth,
               QosReliability.BEST_EFFORT if profile.reliability == ReliabilityPolicy.BEST_EFFORT
               else QosReliability.RELIABLE,
               QosDurability.TRANSIENT_LOCAL if profile.durability == DurabilityPolicy.TRANSIENT_LOCAL
               else QosDurability.VOLATILE,
               infinite, infinite, QosLiveliness.AUTOMATIC, infinite, False)


def qos_profiles(token: str) -> list[dict]:
    """rosbag2's metadata.yaml (version 9) `offered_qos_profiles` entry for a zros QoS token."""
    from rosbags.rosbag2.metadata import dump_qos_v9
    return [dict(profile) for profile in dump_qos_v9([qos_token_to_rosbag2(token)])]


def qos_yaml(token: str) -> str:
    """The same profiles as YAML text: what rosbag2 puts in an MCAP channel's metadata."""
    import yaml
    return yaml.safe_dump(qos_profiles(token), sort_keys=False).strip()


def qos_token_from_rosbag2(profiles: Any) -> str:
    """The zros QoS token of the first rosbag2 profile: a list of rosbags `Qos`, or rosbag2's
    YAML text (what MCAP channel metadata holds). '' when there is none or it cannot be read."""
    from rosbags.interfaces import QosDurability, QosHistory, QosReliability

    from zros.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy
    if isinstance(profiles, str):
        from rosbags.rosbag2.errors import ReaderError
        from rosbags.rosbag2.metadata import parse_qos
        try:
            profiles = parse_qos(profiles)
        except (ReaderError, KeyError, TypeError, ValueError):
            return ''
    if not profiles:
        return ''
    first = profiles[0]
    keep_all = first.history == QosHistory.KEEP_ALL
    return QoSProfile(history=HistoryPolicy.KEEP_ALL if keep_all else HistoryPolicy.KEEP_LAST,
                      depth=0 if keep_all else max(1, int(first.depth)),
                      reliability=ReliabilityPolicy.BEST_EFFORT if first.reliability == QosReliability.BEST_EFFORT
                      else ReliabilityPolicy.RELIABLE,
                      durability=DurabilityPolicy.TRANSIENT_LOCAL
                      if first.durability == QosDurability.TRANSIENT_LOCAL
                      else DurabilityPolicy.VOLATILE).to_token()


class CdrBagWriter:
    """Writes a rosbag2 bag with CDR payloads (rosbags' writer underneath).

    `write()` takes CDR bytes; `CdrCodec` makes them from zros messages.

    Args:
        directory: the bag directory; it must not exist yet (as with ros2 bag record).
        storage: 'mcap' (default) or 'sqlite3'.
    Raises:
        BagError: the directory exists or cannot be created, or the storage is unknown.
    """

    encoding = CDR_ENCODING

    def __init__(self, directory: str | os.PathLike[str], *, storage: str = 'mcap') -> None:
        from rosbags.rosbag2 import StoragePlugin, Writer, WriterError
        if storage not in STORAGES:
            raise BagError(f"unknown storage '{storage}' (choose from {', '.join(STORAGES)})")
        self.directory = Path(directory)
        if self.directory.exists():
            raise BagError(f"output folder '{self.directory}' already exists")
        plugin = StoragePlugin.MCAP if storage == 'mcap' else StoragePlugin.SQLITE3
        self._writer = Writer(self.directory, version=9, storage_plugin=plugin)
        try:
            self._writer.open()
        except (WriterError, OSError) as exc:
            raise BagError(f"cannot create output folder '{self.directory}': {exc}") from None
        self.path = self._writer.storage.path
        self._codec = CdrCodec()
        self._connections: dict[str, Any] = {}
        self._counts: dict[str, int] = {}
        self._closed = False

    @property
    def message_count(self) -> int:
        return sum(self._counts.values())

    @property
    def codec(self) -> CdrCodec:
        """The codec whose typestore holds this bag's types (use it to serialize for `write`)."""
        return self._codec

    def add_topic(self, name: str, type_name: str, *, type_hash: str = '', qos: str = '') -> None:
        """Declare a topic; `type_hash` (zros's) is not stored: rosbag2 keeps the RIHS01 hash."""
        if name in self._connections:
            return
        self._connections[name] = self._writer.add_connection(
            name, type_name, msgdef=self._codec.definition(type_name), rihs01=self._codec.rihs01(type_name),
            serialization_format=CDR_ENCODING, offered_qos_profiles=[qos_token_to_rosbag2(qos)])
        self._counts[name] = 0

    def write(self, topic: str, payload: bytes, *, log_time: int, publish_time: int | None = None) -> None:
        """Append one CDR message of a topic added before (rosbag2 keeps one time: `log_time`)."""
        self._writer.write(self._connections[topic], log_time, payload)
        self._counts[topic] += 1

    def close(self) -> None:
        """Finish the storage file and write metadata.yaml. Idempotent."""
        if self._closed:
            return
        self._closed = True
        self._writer.close()

    def __enter__(self) -> 'CdrBagWriter':
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


class Rosbag2Reader:
    """Reads a rosbag2 bag (directory with metadata.yaml, or a bare .db3/.mcap file) through
    rosbags. Messages keep their CDR bytes; `TopicInfo.encoding` says so.

    Raises:
        BagError: the bag is missing, unreadable or not rosbag2.
    """

    def __init__(self, path: str | os.PathLike[str]) -> None:
        self.path = Path(path)
        if not self.path.exists():
            raise BagError(f"bag '{self.path}' does not exist")
        self._summary = self._read_summary()

    def _open(self) -> Any:
        from rosbags.rosbag2 import Reader, ReaderError
        reader = Reader(self.path)
        try:
            reader.open()
        except (ReaderError, FileNotFoundError, OSError, ValueError) as exc:
            raise BagError(f"cannot read the bag '{self.path}': {exc}") from None
        except Exception as exc:  # noqa: BLE001 - apsw's errors (a corrupt .db3) have no common base here
            raise BagError(f"'{self.path}' is corrupt: {type(exc).__name__}: {exc}") from None
        return reader

    def _read_summary(self) -> BagSummary:
        reader = self._open()
        try:
            topics = []
            for name, info in sorted(reader.topics.items()):
                connection = info.connections[0]
                topics.append(TopicInfo(name, info.msgtype or '', info.msgcount,
                                        connection.ext.serialization_format, connection.digest or '',
                                        qos_token_from_rosbag2(connection.ext.offered_qos_profiles)))
            count = reader.message_count
            files = [p.name for p in self._storage_files()]
            storage_id = 'sqlite3' if any(f.endswith('.db3') for f in files) else 'mcap'
            return BagSummary(files, sum((self._base() / f).stat().st_size for f in files), storage_id,
                              reader.start_time if count else 0, max(reader.end_time - 1, 0) if count else 0,
                              count, topics, True)
        finally:
            reader.close()

    def _base(self) -> Path:
        return self.path if self.path.is_dir() else self.path.parent

    def _storage_files(self) -> list[Path]:
        if not self.path.is_dir():
            return [self.path]
        return sorted(p for p in self.path.iterdir() if p.suffix in ('.db3', '.mcap'))

    def summary(self) -> BagSummary:
        return self._summary

    def messages(self, topics: list[str] | None = None, *, start_time: int | None = None) -> Iterator[BagMessage]:
        """Every message (of `topics`, from `start_time` on) in time order, CDR bytes as stored."""
        reader = self._open()
        try:
            wanted = [c for c in reader.connections if topics is None or c.topic in topics]
            if not wanted:
                return
            try:
                for connection, timestamp, data in reader.messages(connections=wanted, start=start_time):
                    yield BagMessage(connection.topic, connection.msgtype, bytes(data), timestamp, timestamp)
            except Exception as exc:  # noqa: BLE001 - storage errors (apsw, mcap) end the read with one line
                raise BagError(f"'{self.path}' is corrupt: {type(exc).__name__}: {exc}") from None
        finally:
            reader.close()
