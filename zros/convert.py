"""Messages to and from plain data: what `zros topic echo/pub`, `service call` and bags use.

The equivalents of rosidl_runtime_py's `message_to_ordereddict`, `message_to_yaml`,
`message_to_csv` and `set_message_fields`, with errors that name the field path.
"""
from __future__ import annotations

import array
from typing import Any

import numpy as np

from zros.errors import MessageTypeError

__all__ = ['message_to_ordereddict', 'message_to_yaml', 'message_to_csv', 'set_message_fields',
           'message_from_yaml', 'get_field', 'yaml_prototype']


def message_to_ordereddict(msg: Any, *, truncate_length: int | None = None, no_arr: bool = False,
                           no_str: bool = False) -> dict:
    out = {}
    for field in msg._SPEC.fields:
        value = getattr(msg, field.name)
        if no_arr and field.type.is_array:
            out[field.name] = _array_summary(field.type, len(value))
        else:
            out[field.name] = _to_plain(value, truncate_length, no_arr, no_str)
    return out


def _to_plain(value: Any, truncate: int | None, no_arr: bool, no_str: bool) -> Any:
    if hasattr(value, '_FIELDS'):
        return message_to_ordereddict(value, truncate_length=truncate, no_arr=no_arr, no_str=no_str)
    if isinstance(value, (np.ndarray, array.array, list)):
        items = value.tolist() if not isinstance(value, list) else [
            _to_plain(v, truncate, no_arr, no_str) for v in value]
        if truncate is not None and len(items) > truncate:
            items = items[:truncate] + ['...']
        return items
    if isinstance(value, bytes):  # a `byte` field (rclpy's bytes of length 1) as its number
        return value[0]
    if isinstance(value, str):
        if no_str:
            return f'<string length: <{len(value)}>>'
        if truncate is not None and len(value) > truncate:
            return value[:truncate] + '...'
    return value


# The IDL names rosidl gives the .msg primitives (what `ros2 topic echo --no-arr` prints).
_IDL_NAMES = {'bool': 'boolean', 'byte': 'octet', 'char': 'uint8', 'float32': 'float', 'float64': 'double'}


def _array_summary(field_type: Any, length: int) -> str:
    """rosidl_runtime_py's placeholder for an array field under --no-arr, IDL type names and all."""
    name = _IDL_NAMES.get(field_type.base, field_type.base)
    if field_type.array == 'fixed':
        return f'<array type: {name}[{field_type.array_size}]>'
    if field_type.array == 'bounded':
        return f'<sequence type: {name}[{field_type.array_size}], length: {length}>'
    return f'<sequence type: {name}, length: {length}>'


def message_to_yaml(msg: Any, *, truncate_length: int | None = None, no_arr: bool = False,
                    no_str: bool = False, flow_style: bool = False) -> str:
    import yaml
    return yaml.safe_dump(message_to_ordereddict(msg, truncate_length=truncate_length, no_arr=no_arr,
                                                 no_str=no_str),
                          default_flow_style=flow_style, sort_keys=False, allow_unicode=True, width=2**31)


def message_to_csv(msg: Any, *, truncate_length: int | None = None, no_arr: bool = False,
                   no_str: bool = False) -> str:
    """All leaf values in field order, comma-separated (ros2 topic echo --csv)."""
    def leaves(value: Any):
        if isinstance(value, dict):
            for v in value.values():
                yield from leaves(v)
        elif isinstance(value, list):
            for v in value:
                yield from leaves(v)
        else:
            yield value
    plain = message_to_ordereddict(msg, truncate_length=truncate_length, no_arr=no_arr, no_str=no_str)
    return ','.join(str(v) for v in leaves(plain))


def set_message_fields(msg: Any, values: dict, *, _path: str = '') -> Any:
    """Fill `msg` from a (YAML-loaded) mapping; unknown fields and bad values name the path."""
    if values is None:
        return msg
    if not isinstance(values, dict):
        raise MessageTypeError(f"{_path or msg._TYPE}: expected a mapping of fields, got {values!r:.60}")
    for name, value in values.items():
        path = f'{_path}.{name}' if _path else name
        if name not in msg._FIELD_TYPES:
            raise MessageTypeError(
                f"unknown field '{path}' in {msg._TYPE}; fields are: {', '.join(msg._FIELDS) or '(none)'}")
        current = getattr(msg, name)
        try:
            if hasattr(current, '_FIELDS'):
                set_message_fields(current, value, _path=path)
            elif isinstance(current, list) and current is not None and _nested_item_type(msg, name):
                item_type = _nested_item_type(msg, name)
                if not isinstance(value, list):
                    raise MessageTypeError(f"field '{path}' expects a list, got {value!r:.60}")
                setattr(msg, name, [set_message_fields(item_type(), v, _path=f'{path}[{i}]')
                                    for i, v in enumerate(value)])
            else:
                setattr(msg, name, _coerce(value, msg._FIELD_TYPES[name]))
        except MessageTypeError as exc:
            text = str(exc)
            raise MessageTypeError(text if path in text else f"field '{path}': {text}") from None
    return msg


def _nested_item_type(msg: Any, name: str) -> type | None:
    for field in msg._SPEC.fields:
        if field.name == name and field.type.is_array and not field.type.is_primitive:
            from zros.typesupport import get_message
            return get_message(field.type.base)
    return None


def _coerce(value: Any, type_text: str) -> Any:
    """YAML gives ints where floats are meant (`x: 2`) and numbers for strings (`data: 5`)."""
    base = type_text.split('[')[0].split('<=')[0]
    if base in ('string', 'wstring') and isinstance(value, (int, float, bool)) and not isinstance(value, str):
        return str(value).lower() if isinstance(value, bool) else str(value)
    if base in ('string', 'wstring') and isinstance(value, list):
        return [str(v) if not isinstance(v, str) else v for v in value]
    return value


def message_from_yaml(msg_type: type, text: str | None) -> Any:
    """Build a message from ros2-style YAML text such as "{data: hi}" ('' gives the defaults)."""
    import yaml
    msg = msg_type()
    if text is None or not text.strip():
        return msg
    try:
        values = yaml.safe_load(text)
    except yaml.YAMLError as exc:
        mark = getattr(exc, 'problem_mark', None)
        where = f' (line {mark.line + 1}, column {mark.column + 1})' if mark else ''
        problem = getattr(exc, 'problem', None) or str(exc).splitlines()[0]
        raise MessageTypeError(f'invalid YAML for {msg_type._TYPE}{where}: {problem}') from None
    return set_message_fields(msg, values)


def get_field(msg: Any, path: str) -> Any:
    """`a.b.c` inside a message (ros2 topic echo --field); a clear error when it is absent."""
    value = msg
    for part in path.split('.'):
        if not part:
            continue
        if not hasattr(value, '_FIELDS') or part not in value._FIELDS:
            raise MessageTypeError(f"invalid field '{path}' for {msg._TYPE}")
        value = getattr(value, part)
    return value


def yaml_prototype(msg_type: type) -> str:
    """A YAML text of the default message, as `ros2 interface proto` prints it."""
    return message_to_yaml(msg_type())
