"""zros messages to and from rosbridge's JSON, by ROS's JSON conventions.

roslib and every rosbridge client expect what rosbridge_library's message conversion gives:
`uint8[]`/`char[]` as one base64 string (an image or a map is not a list of a million numbers),
`byte` as its number, NaN and infinities as null (JSON has neither), time and duration as
`{sec, nanosec}`. On the way in, a client may leave fields out (their defaults are kept), give a
`builtin_interfaces/Time` as the string "now", and leave out a header's stamp: both mean the
bridge's clock now, as rosbridge does, so a web page can send a goal without knowing ROS time.
Bad input raises MessageTypeError naming the field path, which the bridge turns into a status
message for that client.
"""
from __future__ import annotations

import base64
import binascii
import functools
import math
from typing import Any, Callable

import numpy as np

from zros.errors import MessageTypeError

__all__ = ['message_to_json', 'message_from_json']

_BINARY = frozenset({'uint8', 'char'})
_FLOATS = frozenset({'float32', 'float64'})
_TIME = 'builtin_interfaces/msg/Time'
_HEADER = 'std_msgs/msg/Header'


def message_to_json(msg: Any) -> dict:
    """The rosbridge JSON object of a message (plain dicts, lists, str, numbers, None)."""
    out = {}
    for field in msg._SPEC.fields:
        out[field.name] = _value_to_json(getattr(msg, field.name), field.type)
    return out


def _value_to_json(value: Any, ftype: Any) -> Any:
    if not ftype.is_primitive:
        if ftype.is_array:
            return [message_to_json(item) for item in value]
        return message_to_json(value)
    if ftype.is_array:
        if ftype.base in _BINARY:
            return base64.b64encode(bytes(value)).decode('ascii')
        if ftype.base == 'byte':
            return [item[0] for item in value]
        if ftype.base in _FLOATS:
            floats = np.asarray(value, dtype=np.float64)
            if np.isfinite(floats).all():
                return floats.tolist()
            return [item if math.isfinite(item) else None for item in floats.tolist()]
        return value.tolist() if hasattr(value, 'tolist') else list(value)
    if ftype.base == 'byte':
        return value[0]
    if ftype.base in _FLOATS and not math.isfinite(value):
        return None
    return value


def message_from_json(msg_type: type, data: Any, *, now: Callable[[], Any], _path: str = '') -> Any:
    """A `msg_type` filled from rosbridge JSON; fields left out keep their defaults.

    Args:
        msg_type: the zros message class.
        data: the decoded JSON object (a dict; None gives the default message).
        now: gives a builtin_interfaces/Time for "now" and for a header without a stamp.
    Raises:
        MessageTypeError: not an object, an unknown field, a value of the wrong type or range.
    """
    msg = msg_type()
    if data is None:
        data = {}
    if not isinstance(data, dict):
        raise MessageTypeError(f'{_path or msg_type._TYPE}: expected a JSON object for {msg_type._TYPE}, '
                               f'got {_json_kind(data)}')
    if msg_type._TYPE == _HEADER and 'stamp' not in data:
        msg.stamp = now()
    for name, value in data.items():
        path = f'{_path}.{name}' if _path else name
        field_type = _field_types(msg_type).get(name)
        if field_type is None:
            raise MessageTypeError(f"unknown field '{path}' in {msg_type._TYPE}; "
                                   f"fields are: {', '.join(msg_type._FIELDS) or '(none)'}")
        try:
            setattr(msg, name, _value_from_json(value, field_type, now, path))
        except MessageTypeError as exc:
            text = str(exc)
            raise MessageTypeError(text if f"'{path}" in text else f"field '{path}': {text}") from None
    if _HEADER in (t.base for t in _field_types(msg_type).values()) and 'header' not in data:
        for field in msg_type._SPEC.fields:
            if field.type.base == _HEADER and not field.type.is_array:
                getattr(msg, field.name).stamp = now()
    return msg


def _value_from_json(value: Any, ftype: Any, now: Callable[[], Any], path: str) -> Any:
    if not ftype.is_primitive:
        from zros.typesupport import get_message
        nested = get_message(ftype.base)
        if ftype.is_array:
            if not isinstance(value, list):
                raise MessageTypeError(f"field '{path}' expects a list, got {_json_kind(value)}")
            return [message_from_json(nested, item, now=now, _path=f'{path}[{i}]') for i, item in enumerate(value)]
        if ftype.base == _TIME and value == 'now':
            return now()
        return message_from_json(nested, value, now=now, _path=path)
    if ftype.is_array:
        if ftype.base in _BINARY and isinstance(value, str):
            try:
                return base64.b64decode(value, validate=True)
            except binascii.Error:
                raise MessageTypeError(f"field '{path}' expects base64 text or a list of numbers") from None
        if not isinstance(value, list):
            raise MessageTypeError(f"field '{path}' expects a list, got {_json_kind(value)}")
        if ftype.base == 'byte':
            return [_byte(item, path) for item in value]
        if ftype.base in _FLOATS:
            return [math.nan if item is None else item for item in value]
        return value
    if ftype.base == 'byte':
        return _byte(value, path)
    if ftype.base in _FLOATS and value is None:
        return math.nan
    if isinstance(value, (dict, list)):
        raise MessageTypeError(f"field '{path}' expects a {ftype.base}, got {_json_kind(value)}")
    return value


def _byte(value: Any, path: str) -> bytes:
    if isinstance(value, bool) or not isinstance(value, int) or not 0 <= value <= 255:
        raise MessageTypeError(f"field '{path}' expects a byte (0..255), got {value!r:.40}")
    return bytes([value])


@functools.lru_cache(maxsize=None)
def _field_types(msg_type: type) -> dict[str, Any]:
    return {field.name: field.type for field in msg_type._SPEC.fields}


def _json_kind(value: Any) -> str:
    """The JSON name of a value's kind, for errors a web developer reads."""
    if value is None:
        return 'null'
    if isinstance(value, bool):
        return 'a boolean'
    if isinstance(value, (int, float)):
        return f'the number {value!r}'
    if isinstance(value, str):
        return f'the string {value!r:.40}'
    return 'a list' if isinstance(value, list) else 'an object'
