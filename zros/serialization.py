"""Messages as ROS 2's serialized bytes (rclpy.serialization): CDR, little-endian, with its
4-byte encapsulation header, exactly what rmw hands a ROS 2 program.

zros itself sends MessagePack between zros programs; code that stores or forwards
`serialize_message` output expects CDR, so these go through the bag's CDR codec (rosbags'
typestore; the `bag` extra).
"""
from __future__ import annotations

import threading
from typing import Any, TypeVar

__all__ = ['serialize_message', 'deserialize_message']

MsgT = TypeVar('MsgT')

_lock = threading.Lock()   # the codec is not thread-safe; one codec serves the process
_codec: Any = None


def _with_codec(work: Any) -> Any:
    global _codec
    from zros.extras import missing_extra
    with _lock:
        try:
            if _codec is None:
                from zros.bag.cdr import CdrCodec
                _codec = CdrCodec()
            return work(_codec)
        except ImportError as exc:
            raise (missing_extra(exc, 'rclpy.serialization') or exc) from None


def serialize_message(message: Any) -> bytes:
    """Serialize a message as ROS 2 does.

    :param message: A message instance (of any type on the interface path).
    :return: Its CDR bytes.
    :raises TypeError: If `message` is not a message.
    """
    if not hasattr(type(message), '_TYPE'):
        raise TypeError(f'serialize_message needs a message, got {type(message).__name__}')
    return _with_codec(lambda codec: codec.serialize(message))


def deserialize_message(serialized_message: bytes, message_type: type[MsgT]) -> MsgT:
    """Read a message of `message_type` back from CDR bytes.

    :param serialized_message: Bytes from `serialize_message` (or from a ROS 2 program).
    :param message_type: The message class.
    :return: A new `message_type` instance.
    :raises TypeError: If `message_type` is not a message class.
    :raises BagError: If the bytes are not a CDR `message_type`.
    """
    if not hasattr(message_type, '_TYPE'):
        raise TypeError(f'deserialize_message needs a message class, got {message_type!r}')
    return _with_codec(lambda codec: codec.deserialize(serialized_message, message_type))
