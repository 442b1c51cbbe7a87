"""The attachment every zros sample, request and reply carries (protocol v1, docs/protocol.md).

    b'Z1' | gid (16) | sequence (u64 LE) | source time ns (i64 LE) | type hash (8) | type name

Writers (publishers, clients) stamp it; readers (subscriptions, services) use it to refuse
the wrong type, count lost messages per writer and report source times.
"""
from __future__ import annotations

import itertools
import os
import struct
import time

__all__ = ['MAGIC', 'TYPE_AT', 'AttachmentWriter', 'read_header', 'writer_sequence', 'type_tail',
           'describe_type']

MAGIC = b'Z1'
_GID_AT = len(MAGIC)
_SEQ_AT = _GID_AT + 16
_SEQ_TIME = struct.Struct('<Qq')
TYPE_AT = _SEQ_AT + _SEQ_TIME.size


def type_tail(iface_type: type) -> bytes:
    """The type-identifying end of an attachment: hash bytes then the type name."""
    return bytes.fromhex(iface_type._HASH) + iface_type._TYPE.encode()


class AttachmentWriter:
    """Stamps a writer's attachments; one per publisher or client (its own gid and sequence)."""

    __slots__ = ('_head', '_tail', '_seq', '_pack')

    def __init__(self, iface_type: type) -> None:
        self._head = MAGIC + os.urandom(16)
        self._tail = type_tail(iface_type)
        self._seq = itertools.count(1)
        self._pack = _SEQ_TIME.pack

    def next(self) -> bytes:
        return self._head + self._pack(next(self._seq), time.time_ns()) + self._tail


def read_header(attachment: bytes) -> tuple[bytes, int, int, bytes] | None:
    """(gid, sequence, source time ns, type tail), or None when the sample did not come from a
    zros writer. A plain tuple: this runs once per received message."""
    if attachment[:_GID_AT] != MAGIC or len(attachment) < TYPE_AT:
        return None
    seq, source_ns = _SEQ_TIME.unpack_from(attachment, _SEQ_AT)
    return attachment[_GID_AT:_SEQ_AT], seq, source_ns, attachment[TYPE_AT:]


_unpack_seq = struct.Struct('<Q').unpack_from


def writer_sequence(attachment: bytes) -> tuple[bytes, int] | None:
    """(gid, sequence number) of a zros attachment, None for others. The cheap part of
    read_header, for Zenoh's receive thread."""
    if attachment[:_GID_AT] != MAGIC or len(attachment) < TYPE_AT:
        return None
    return attachment[_GID_AT:_SEQ_AT], _unpack_seq(attachment, _SEQ_AT)[0]


def describe_type(tail: bytes) -> tuple[str, str]:
    """(type name, hash hex) from an attachment's tail, for error messages."""
    return tail[8:].decode(errors='replace'), tail[:8].hex()
