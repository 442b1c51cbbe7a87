"""What every zros sample, request and reply carries besides its payload (protocol v2,
docs/protocol.md), and the checks a receiver makes before decoding one.

The attachment:

    b'Z2' | gid (16) | sequence (u64 LE) | source time ns (i64 LE) | type hash (8) | type name

Writers (publishers, clients) stamp it; readers (subscriptions, services) use it to refuse the
wrong type, count lost messages per writer and report source times. A payload without it (from
a plain Zenoh client) is decoded strictly as the reader's type. Readers also refuse payloads
larger than their limit (`ZROS_MAX_MESSAGE_SIZE`, `ZROS_MAX_REQUEST_SIZE`) before decoding.
"""
from __future__ import annotations

import itertools
import os
import re
import struct
import time
from typing import Any

from zros.errors import ZrosError

__all__ = ['MAGIC', 'PROTOCOL_VERSION', 'GID_AT', 'WRITER_STAMP', 'TYPE_AT', 'AttachmentWriter',
           'read_header', 'type_tail', 'describe_type', 'mismatch_reason', 'foreign_protocol',
           'max_message_size', 'max_request_size', 'parse_size', 'DEFAULT_MAX_MESSAGE_SIZE',
           'DEFAULT_MAX_REQUEST_SIZE', 'WAKE', 'is_wake']

PROTOCOL_VERSION = 2
MAGIC = b'Z2'
_OLD_MAGIC = re.compile(rb'Z[0-9]')
#: The writer's gid, its sequence number and source time ns, read at once from GID_AT; the
#: type starts at TYPE_AT.
GID_AT = len(MAGIC)
WRITER_STAMP = struct.Struct('<16sQq')
TYPE_AT = GID_AT + WRITER_STAMP.size

#: What a subscription or a client accepts per message unless ZROS_MAX_MESSAGE_SIZE says
#: otherwise: room for 4K RGB images and large point clouds, not for a runaway sender.
DEFAULT_MAX_MESSAGE_SIZE = 256 << 20
#: What a service server accepts per request unless ZROS_MAX_REQUEST_SIZE says otherwise
#: (a request is decoded and answered on the executor, so a huge one stalls other callbacks).
DEFAULT_MAX_REQUEST_SIZE = 16 << 20


def type_tail(iface_type: type) -> bytes:
    """The type-identifying end of an attachment: hash bytes then the type name."""
    return bytes.fromhex(iface_type._HASH) + iface_type._TYPE.encode()


class AttachmentWriter:
    """Stamps a writer's attachments; one per publisher or client (its own gid and sequence).

    `next()` makes the next attachment. It runs once per message sent, so it is a closure over
    what it packs (no attribute lookups, no method call behind it)."""

    __slots__ = ('_gid', '_tail', 'next')

    def __init__(self, iface_type: type) -> None:
        self._gid = gid = os.urandom(16)
        self._tail = tail = type_tail(iface_type)
        pack = struct.Struct(f'<2s16sQq{len(tail)}s').pack
        sequence = itertools.count(1).__next__
        now_ns = time.time_ns

        def next() -> bytes:  # noqa: A001 - the name callers have always used
            return pack(MAGIC, gid, sequence(), now_ns(), tail)
        self.next = next


# The attachment of a wake-up: an empty DELETE that an executor receiving from a subscription's
# channel itself (zros.executors, the pull) puts on that subscription's key, local to the
# session, so that its blocking receive returns when other work comes. Any other subscriber of
# the key in the same session ignores it (`is_wake`).
WAKE = b'Z-wake'


def is_wake(sample: Any) -> bool:
    """Whether a Zenoh sample is an executor's wake-up (WAKE), not a message."""
    attachment = sample.attachment
    return attachment is not None and attachment.to_bytes() == WAKE


def read_header(attachment: bytes) -> tuple[bytes, int, int, bytes] | None:
    """(gid, sequence, source time ns, type tail), or None when the sample did not come from a
    zros writer of this protocol version. A plain tuple: this runs once per received message."""
    if attachment[:GID_AT] != MAGIC or len(attachment) < TYPE_AT:
        return None
    gid, seq, source_ns = WRITER_STAMP.unpack_from(attachment, GID_AT)
    return gid, seq, source_ns, attachment[TYPE_AT:]


def describe_type(tail: bytes) -> tuple[str, str]:
    """(type name, hash hex) from an attachment's tail, for error messages."""
    return tail[8:].decode(errors='replace'), tail[:8].hex()


def mismatch_reason(tail: bytes, iface_type: type, sender: str) -> str:
    """Why a sample whose attachment names `tail` is not for `iface_type` (`sender` is 'a
    publisher' or 'the client'): another type, or the same type name with another definition."""
    their_type, their_hash = describe_type(tail)
    if their_type == iface_type._TYPE:
        return (f'{sender} sends {their_type} with a different definition (type hash {their_hash}, '
                f'this side has {iface_type._HASH}): the two sides were built from different '
                f'{their_type.rsplit("/", 1)[-1]} interface files')
    return f'{sender} sends {their_type}, this side expects {iface_type._TYPE}'


def foreign_protocol(attachment: bytes) -> str | None:
    """A one-line reason when `attachment` is a zros attachment of another protocol version
    (its payload cannot be read by this one), else None."""
    if len(attachment) >= TYPE_AT and attachment[:GID_AT] != MAGIC and _OLD_MAGIC.fullmatch(attachment[:GID_AT]):
        version = attachment[1:2].decode()
        return (f'the sender speaks zros protocol v{version}, this node speaks v{PROTOCOL_VERSION} '
                '(run the same zros version on both sides)')
    return None


def parse_size(text: str, what: str) -> int:
    """'1048576', '64K', '16M' or '1G' (binary units) as a byte count; ZrosError otherwise."""
    match = re.fullmatch(r'\s*(\d+)\s*([kKmMgG]?)(i?[bB])?\s*', text)
    if not match:
        raise ZrosError(f"{what}: '{text}' is not a size; expected bytes or a number with K, M or G, e.g. 16M")
    return int(match.group(1)) << {'': 0, 'k': 10, 'm': 20, 'g': 30}[match.group(2).lower()]


def _size_setting(name: str, default: int) -> int:
    text = os.environ.get(name)
    return default if not text else parse_size(text, name)


def max_message_size() -> int:
    """The largest topic message (or service reply) a reader accepts, in bytes."""
    return _size_setting('ZROS_MAX_MESSAGE_SIZE', DEFAULT_MAX_MESSAGE_SIZE)


def max_request_size() -> int:
    """The largest service request a server accepts, in bytes."""
    return _size_setting('ZROS_MAX_REQUEST_SIZE', DEFAULT_MAX_REQUEST_SIZE)
