"""Message fields as rqt's tools use them: plot paths, message trees, request forms.

Plain Python on message classes and their specs (no node, no browser), so the Plot, Topic
monitor and Service caller pages are tested without either:

    topic, parts = split_plot_path('/turtle1/pose/x', topics)     # ('/turtle1/pose', ['x'])
    check_field(Pose, parts)                                       # 'float32', or FieldError
    field_value(msg, parts)                                        # 5.54
    form_fields(Spawn.Request)                                     # x, y, theta, name with types
    fill_request(Spawn.Request, {'x': 2.0, 'name': 'bob'})         # checked before sending
"""
from __future__ import annotations

import html
import re
from typing import Any, NamedTuple

from zros.errors import MessageTypeError

__all__ = ['FieldError', 'parse_field', 'split_plot_path', 'check_field', 'field_value', 'numeric_fields',
           'message_tree_html', 'FormField', 'form_fields', 'fill_request']

_NUMERIC = {'bool', 'byte', 'char', 'float32', 'float64', 'int8', 'uint8', 'int16', 'uint16', 'int32', 'uint32',
            'int64', 'uint64'}
_INT_RANGES = {'int8': (-2 ** 7, 2 ** 7 - 1), 'uint8': (0, 2 ** 8 - 1), 'int16': (-2 ** 15, 2 ** 15 - 1),
               'uint16': (0, 2 ** 16 - 1), 'int32': (-2 ** 31, 2 ** 31 - 1), 'uint32': (0, 2 ** 32 - 1),
               'int64': (-2 ** 63, 2 ** 63 - 1), 'uint64': (0, 2 ** 64 - 1), 'byte': (0, 255), 'char': (0, 255)}
_PART = re.compile(r'([^/.\[\]]+)|\[(\d+)\]')


class FieldError(ValueError):
    """A field path that does not exist in the message type, or does not lead to a number."""


def parse_field(path: str) -> list[str | int]:
    """`pose.position.x`, `pose/position/x`, `ranges[3]` or `ranges/3` as [names and indices]."""
    parts: list[str | int] = []
    for match in _PART.finditer(path):
        name, index = match.groups()
        if index is not None:
            parts.append(int(index))
        elif name.isdigit():
            parts.append(int(name))
        else:
            parts.append(name)
    return parts


def split_plot_path(path: str, topics: list[str]) -> tuple[str, list[str | int]]:
    """rqt_plot's `/topic/field/...`: the longest known topic the path starts with, and the rest.

    Raises:
        FieldError: no topic of the graph is a prefix of `path`.
    """
    path = '/' + path.strip().lstrip('/')
    base = path.split('[', 1)[0]
    for topic in sorted(topics, key=len, reverse=True):
        if base == topic or base.startswith(topic.rstrip('/') + '/'):
            return topic, parse_field(path[len(topic):])
    raise FieldError(f'{path}: no topic of the graph is a prefix of this path (not published yet?)')


def _spec_field(msg_type: type, name: str) -> Any:
    for field in msg_type._SPEC.fields:
        if field.name == name:
            return field
    fields = ', '.join(f.name for f in msg_type._SPEC.fields) or '(none)'
    raise FieldError(f"{msg_type._TYPE} has no field '{name}' (its fields: {fields})")


def check_field(msg_type: type, parts: list[str | int]) -> str:
    """The primitive type `parts` leads to in `msg_type` ('float32', ...).

    Raises:
        FieldError: a part does not exist, an index is applied to a non-array, or the path
            ends at a message, an array or a string (nothing to plot).
    """
    from zros.typesupport import get_message
    current, field_type, indexed = msg_type, None, True
    shown = ''
    for part in parts:
        if isinstance(part, int):
            if field_type is None or not field_type.is_array or indexed:
                raise FieldError(f"[{part}] applies to an array only, not to {shown or msg_type._TYPE}")
            if field_type.array == 'fixed' and part >= field_type.array_size:
                raise FieldError(f'index {part} is beyond the {field_type.array_size} elements of {shown}')
            indexed = True
            shown += f'[{part}]'
            if not field_type.is_primitive:
                current = get_message(field_type.base)
            continue
        if field_type is not None and (field_type.is_primitive or not indexed):
            raise FieldError(f"{shown} is {'an array' if not indexed else field_type.base}: no field '{part}' in it")
        field = _spec_field(current, part)
        field_type, indexed = field.type, not field.type.is_array
        shown += f'/{part}' if shown else part
        if not field_type.is_primitive and indexed:
            current = get_message(field_type.base)
    if field_type is None:
        raise FieldError(f'name a field of {msg_type._TYPE} to plot, e.g. {(numeric_fields(msg_type) or ["..."])[0]}')
    if not indexed:
        raise FieldError(f'{shown} is an array: add an index, e.g. {shown}[0]')
    if field_type.base not in _NUMERIC:
        raise FieldError(f'{shown} is {field_type.base}: only numbers can be plotted')
    return field_type.base


def field_value(msg: Any, parts: list[str | int]) -> float:
    """The number at `parts` in `msg` (bools as 0/1).

    Raises:
        FieldError: an index is beyond this message's array.
    """
    value = msg
    for part in parts:
        if isinstance(part, int):
            if part >= len(value):
                raise FieldError(f'index {part} is beyond the {len(value)} elements of this message')
            value = value[part]
        else:
            value = getattr(value, part)
    if isinstance(value, bytes):
        value = value[0] if value else 0
    return float(value)


def numeric_fields(msg_type: type, *, depth: int = 4, array_items: int = 2) -> list[str]:
    """Plottable paths in `msg_type` ('x', 'twist/twist/linear/x', 'ranges[0]'), for the picker."""
    from zros.typesupport import get_message
    out: list[str] = []

    def walk(cls: type, prefix: str, level: int) -> None:
        for field in cls._SPEC.fields:
            path = f'{prefix}{field.name}'
            items = [''] if not field.type.is_array else [f'[{i}]' for i in range(
                min(array_items, field.type.array_size or array_items))]
            for item in items:
                if field.type.is_primitive:
                    if field.type.base in _NUMERIC:
                        out.append(path + item)
                elif level < depth:
                    walk(get_message(field.type.base), f'{path}{item}/', level + 1)
    walk(msg_type, '', 0)
    return out


def message_tree_html(value: Any, *, max_items: int = 8) -> str:
    """A message (as `message_to_ordereddict` gives it) as nested, open <details> elements."""
    def render(item: Any, name: str) -> str:
        label = f'<span style="color:#1d4ed8">{html.escape(name)}</span>'
        if isinstance(item, dict):
            inner = ''.join(render(v, k) for k, v in item.items())
            return f'<details open><summary>{label}</summary><div style="margin-left:14px">{inner}</div></details>'
        if isinstance(item, list) and item and isinstance(item[0], dict):
            inner = ''.join(render(v, f'[{i}]') for i, v in enumerate(item[:max_items]))
            more = f'<div style="color:#888">… {len(item)} items</div>' if len(item) > max_items else ''
            return (f'<details><summary>{label} <span style="color:#888">[{len(item)}]</span></summary>'
                    f'<div style="margin-left:14px">{inner}{more}</div></details>')
        if isinstance(item, list):
            shown = ', '.join(_short(v) for v in item[:max_items])
            text = f'[{shown}{", …" if len(item) > max_items else ""}]' + (
                f' <span style="color:#888">({len(item)})</span>' if len(item) > max_items else '')
            return f'<div>{label}: {text}</div>'
        return f'<div>{label}: {html.escape(_short(item))}</div>'
    if not isinstance(value, dict):
        return render(value, 'data')
    return ''.join(render(v, k) for k, v in value.items())


def _short(value: Any) -> str:
    if isinstance(value, float):
        return f'{value:.6g}'
    text = repr(value) if isinstance(value, str) else str(value)
    return text if len(text) <= 80 else text[:77] + '…'


class FormField(NamedTuple):
    """One input of a request form: `path` ('pose/x'), `kind` ('int', 'float', 'bool',
    'text' or 'yaml' for arrays), the default shown, and the IDL type as written."""
    path: str
    kind: str
    default: Any
    type_text: str


def form_fields(msg_type: type, *, depth: int = 4) -> list[FormField]:
    """The inputs of a form for `msg_type`: its primitive fields, nested messages flattened
    (`header/frame_id`), arrays as YAML text."""
    import yaml

    from zros.convert import message_to_ordereddict
    default = message_to_ordereddict(msg_type())
    out: list[FormField] = []

    def walk(cls: type, values: dict, prefix: str, level: int) -> None:
        from zros.typesupport import get_message
        for field in cls._SPEC.fields:
            path, value, kind_of = f'{prefix}{field.name}', values[field.name], field.type
            if kind_of.is_array:
                out.append(FormField(path, 'yaml', yaml.safe_dump(value, default_flow_style=True).strip(),
                                     str(kind_of)))
            elif not kind_of.is_primitive:
                if level < depth:
                    walk(get_message(kind_of.base), value, path + '/', level + 1)
            elif kind_of.base == 'bool':
                out.append(FormField(path, 'bool', bool(value), 'bool'))
            elif kind_of.base in _INT_RANGES:
                out.append(FormField(path, 'int', int(value), kind_of.base))
            elif kind_of.base in ('float32', 'float64'):
                out.append(FormField(path, 'float', float(value), kind_of.base))
            else:
                out.append(FormField(path, 'text', str(value), str(kind_of)))
    walk(msg_type, default, '', 0)
    return out


def fill_request(msg_type: type, values: dict[str, Any]) -> Any:
    """A `msg_type` from form values keyed by FormField.path, each checked against its type.

    Raises:
        FieldError: a value does not fit its field (an int out of range, bad YAML, ...), named
            by its path.
    """
    import yaml

    from zros.convert import set_message_fields
    fields = {f.path: f for f in form_fields(msg_type)}
    tree: dict[str, Any] = {}
    for path, value in values.items():
        field = fields.get(path)
        if field is None:
            raise FieldError(f"{msg_type._TYPE} has no field '{path}'")
        if field.kind == 'int':
            if isinstance(value, float) and not value.is_integer() or isinstance(value, bool):
                raise FieldError(f'{path}: {field.type_text} needs a whole number, got {value}')
            low, high = _INT_RANGES[field.type_text]
            value = int(value)
            if not low <= value <= high:
                raise FieldError(f'{path}: {value} is outside {field.type_text} ({low}..{high})')
        elif field.kind == 'float':
            value = float(value)
        elif field.kind == 'yaml':
            try:
                value = yaml.safe_load(str(value)) if str(value).strip() else []
            except yaml.YAMLError:
                raise FieldError(f'{path}: not a YAML list: {value!r:.60}') from None
            if not isinstance(value, list):
                raise FieldError(f'{path}: {field.type_text} needs a list such as [1, 2], got {value!r:.60}')
        node = tree
        *heads, leaf = path.split('/')
        for head in heads:
            node = node.setdefault(head, {})
        node[leaf] = value
    try:
        return set_message_fields(msg_type(), tree)
    except (MessageTypeError, TypeError, ValueError, OverflowError) as exc:
        raise FieldError(str(exc)) from None
