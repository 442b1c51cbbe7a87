"""`zros bag convert`: a zros bag to a rosbag2 (CDR) bag that ROS tools read, and back.

Each message is decoded with zros's definition of its type and re-encoded in the other format;
timestamps, topic order, QoS and definitions are kept. A message that does not decode is
skipped and counted (the caller reports the count), so one bad payload does not lose a bag.
"""
from __future__ import annotations

import os
from typing import Any, Callable

from zros.bag.cdr import CDR_ENCODING, CdrCodec
from zros.bag.definition import MESSAGE_ENCODING
from zros.bag.errors import BagError

__all__ = ['convert', 'open_writer', 'FORMATS']

#: `--format` values: zros's own (MessagePack payloads) and ROS 2's (CDR payloads).
FORMATS = (MESSAGE_ENCODING, CDR_ENCODING)


def open_writer(output: str | os.PathLike[str], *, format: str = CDR_ENCODING, storage: str = 'mcap') -> Any:
    """The writer for a new bag directory of `format` ('cdr', what ROS tools read, by default; or
    'msgpack') in `storage`.

    Raises:
        BagError: unknown format or storage, or the directory cannot be made.
    """
    if format == CDR_ENCODING:
        from zros.bag.rosbag2 import CdrBagWriter
        return CdrBagWriter(output, storage=storage)
    if format != MESSAGE_ENCODING:
        raise BagError(f"unknown format '{format}' (choose from {', '.join(FORMATS)})")
    if storage != 'mcap':
        raise BagError(f"a {MESSAGE_ENCODING} bag is stored as mcap only (got --storage {storage}); "
                       f'use --format {CDR_ENCODING} for sqlite3')
    from zros.bag.writer import BagWriter
    return BagWriter(output)


def _transcoder(source: str, target: str, msg_type: type, codec: CdrCodec) -> Callable[[bytes], bytes]:
    from zros.message import deserialize, serialize
    if source == target:
        return lambda data: data
    if source == MESSAGE_ENCODING:
        return lambda data: codec.serialize(deserialize(data, msg_type))
    return lambda data: serialize(codec.deserialize(data, msg_type))


def convert(source: str | os.PathLike[str], output: str | os.PathLike[str], *, format: str,
            storage: str = 'mcap', log: Callable[[str], None] = print) -> tuple[int, int]:
    """Write the bag at `source` as a new `format` bag at `output`.

    Returns:
        (messages written, messages skipped because they did not decode).
    Raises:
        BagError: the source cannot be read, or a topic's type is not on the interface path.
    """
    from zros.bag.reader import open_bag
    from zros.errors import DecodeError, ZrosError
    from zros.typesupport import get_message
    reader = open_bag(source)
    summary = reader.summary()
    types = {}
    for info in summary.topics:
        if info.encoding not in FORMATS:
            raise BagError(f"topic '{info.name}' is encoded as '{info.encoding}': only "
                           f"{' and '.join(FORMATS)} bags can be converted")
        try:
            types[info.name] = get_message(info.type)
        except ZrosError as exc:
            raise BagError(f"cannot convert topic '{info.name}': {exc}") from None
    writer = open_writer(output, format=format, storage=storage)
    codec = writer.codec if format == CDR_ENCODING else CdrCodec()
    written = skipped = 0
    try:
        transcoders = {}
        for info in summary.topics:
            msg_type = types[info.name]
            transcoders[info.name] = _transcoder(info.encoding, format, msg_type, codec)
            writer.add_topic(info.name, info.type, type_hash=msg_type._HASH, qos=info.qos)
        for message in reader.messages():
            try:
                data = transcoders[message.topic](message.data)
            except (BagError, DecodeError, ValueError, TypeError) as exc:
                if not skipped:
                    log(f"[WARN] '{message.topic}': skipping messages that do not decode: {exc}")
                skipped += 1
                continue
            writer.write(message.topic, data, log_time=message.log_time, publish_time=message.publish_time)
            written += 1
    finally:
        writer.close()
    return written, skipped
