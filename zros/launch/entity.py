"""YAML launch files as entities that remember where every key and value was written.

The ROS 2 YAML frontend works on plain dicts, so its errors can only name the tag. Here the
loader keeps the line of each mapping key, each value and each list item, so every error can
say `file:line: <tag>: <key>: reason`. `Entity.get_attr` is launch_yaml's typed accessor
(no coercion: `'2'` is a string, `2` an int), and `Entity.assert_complete` rejects keys that no
parser asked for, the way launch_yaml rejects "Unexpected key(s)".
"""
from __future__ import annotations

import typing
from pathlib import Path
from typing import Any

import yaml

from zros.launch.errors import LaunchFileError, Origin

__all__ = ['Entity', 'YamlMap', 'YamlList', 'load_yaml', 'load_launch_entities', 'load_launch_root', 'Scalar',
           'checked_value', 'normalized_type']


class YamlMap(dict):
    """A mapping from a YAML file, with the line of each key and value (1-based)."""

    line: int = 0
    key_lines: dict
    value_lines: dict


class YamlList(list):
    """A sequence from a YAML file, with the line of each item (1-based)."""

    line: int = 0
    item_lines: list


class _LineLoader(yaml.SafeLoader):
    """SafeLoader that builds YamlMap / YamlList and refuses duplicate keys."""


def _construct_map(loader: _LineLoader, node: yaml.MappingNode):
    data = YamlMap()
    data.line = node.start_mark.line + 1
    data.key_lines, data.value_lines = {}, {}
    yield data
    loader.flatten_mapping(node)
    for key_node, value_node in node.value:
        key = loader.construct_object(key_node, deep=True)
        try:
            hash(key)
        except TypeError:
            raise yaml.constructor.ConstructorError(
                None, None, 'a mapping key must be a plain value', key_node.start_mark) from None
        if key in data:
            raise yaml.constructor.ConstructorError(
                None, None, f"duplicate key '{key}'", key_node.start_mark)
        data[key] = loader.construct_object(value_node, deep=True)
        data.key_lines[key] = key_node.start_mark.line + 1
        data.value_lines[key] = value_node.start_mark.line + 1


def _construct_list(loader: _LineLoader, node: yaml.SequenceNode):
    data = YamlList()
    data.line = node.start_mark.line + 1
    data.item_lines = [item.start_mark.line + 1 for item in node.value]
    yield data
    data.extend(loader.construct_object(item, deep=True) for item in node.value)


_LineLoader.add_constructor('tag:yaml.org,2002:map', _construct_map)
_LineLoader.add_constructor('tag:yaml.org,2002:seq', _construct_list)


def load_yaml(path: str | Path, text: str | None = None) -> Any:
    """Parse a YAML file keeping line numbers; LaunchFileError `file:line: invalid YAML: ...`."""
    path = str(path)
    if text is None:
        from zros.launch.files import read_text
        text = read_text(path)
    try:
        return yaml.load(text, Loader=_LineLoader)  # noqa: S506 - a SafeLoader subclass
    except yaml.MarkedYAMLError as exc:
        mark = exc.problem_mark or exc.context_mark
        line = mark.line + 1 if mark is not None else 1
        problem = exc.problem or exc.context or 'syntax error'
        raise LaunchFileError(None, f'{path}:{line}: invalid YAML: {problem}') from None
    except yaml.YAMLError as exc:
        raise LaunchFileError(None, f'{path}:1: invalid YAML: {exc}') from None


class Scalar:
    """`get_attr(data_type=Scalar)`: a string, number or bool, returned as a string (a bool as
    'true' / 'false', the spelling conditions understand). For values such as `arg default`,
    where users write `default: 0` as often as `default: '0'`."""


def _type_name(value: Any) -> str:
    if isinstance(value, bool):
        return 'a bool'
    if isinstance(value, int):
        return 'an int'
    if isinstance(value, float):
        return 'a float'
    if isinstance(value, str):
        return 'a string'
    if isinstance(value, list):
        return 'a list'
    if isinstance(value, dict):
        return 'a mapping'
    return 'null' if value is None else type(value).__name__


def _wrong(origin: Origin, value: Any, expected: str) -> LaunchFileError:
    return LaunchFileError(origin, f'expected {expected}, got {_type_name(value)}'
                           + (f' {value!r}' if not isinstance(value, (list, dict)) else ''))


def normalized_type(data_type: Any) -> Any:
    """`data_type` as `get_attr` compares it: launch writes `typing.List[str]` where zros writes
    `list[str]`, and a list of entities of a format's own class is `list[Entity]`."""
    if data_type is None:
        return Any   # launch's "whatever the file wrote"
    if typing.get_origin(data_type) is list:
        (item,) = typing.get_args(data_type) or (str,)
        if isinstance(item, type) and issubclass(item, Entity):
            return list[Entity]
        return list[item]
    return data_type


def checked_value(value: Any, data_type: Any, origin: Origin) -> Any:
    """`value` as `data_type` (`str`, `Scalar`, `bool`, `int`, `float`, `list[str]`, a list of
    bool / int / float, `Any`), the
    check both front ends' `get_attr` make once they have the value.

    Raises:
        LaunchFileError: at `origin`, `expected an int, got a string '2'`.
    """
    if data_type is Any:
        return value
    if data_type is str:
        if not isinstance(value, str):
            raise _wrong(origin, value, 'a string')
        return value
    if data_type is Scalar:
        if isinstance(value, bool):
            return 'true' if value else 'false'
        if isinstance(value, (str, int, float)):
            return str(value)
        raise _wrong(origin, value, 'a string, number or bool')
    if data_type is bool:
        if not isinstance(value, bool):
            raise _wrong(origin, value, 'a bool (true or false)')
        return value
    if data_type is int:
        if isinstance(value, bool) or not isinstance(value, int):
            raise _wrong(origin, value, 'an int')
        return value
    if data_type is float:
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise _wrong(origin, value, 'a number')
        return float(value)
    if data_type == list[str]:
        if not isinstance(value, list) or not all(isinstance(v, (str, int, float)) for v in value):
            raise _wrong(origin, value, 'a list of strings')
        return [str(v) for v in value]
    if typing.get_origin(data_type) is list and typing.get_args(data_type)[0] in (bool, int, float):
        if not isinstance(value, list):
            raise _wrong(origin, value, 'a list')
        return [checked_value(item, typing.get_args(data_type)[0], origin) for item in value]
    raise TypeError(f'unsupported data_type {data_type!r}')  # a bug in a parser, not the file


class Entity:
    """One tag of a launch file (`{node: {...}}`) or one item of a nested list (`remap`, `param`).

    Constructed by `load_launch_entities` and by `get_attr(..., data_type=list[Entity])`;
    parsers read it through `get_attr` and finish with `assert_complete()`.
    """

    def __init__(self, type_name: str, body: Any, *, path: str, line: int,
                 parent: 'Entity | None' = None) -> None:
        self.type_name = type_name
        self.path = path
        self.line = line
        self.parent = parent
        self._body = body
        self._read: set[str] = set()
        self._asked: set[str] = set()   # every key a parser looked for: this tag's vocabulary

    def __repr__(self) -> str:
        return f'<Entity {self.type_name} at {self.path}:{self.line}>'

    # -- where -------------------------------------------------------------------------------
    @property
    def origin(self) -> Origin:
        return Origin(self.path, self.line, self.type_name)

    def key_line(self, key: str) -> int:
        if isinstance(self._body, YamlMap):
            return self._body.key_lines.get(key, self.line)
        return self.line

    def origin_of(self, key: str | None) -> Origin:
        """Where `key` of this entity was written (the entity itself for None)."""
        if key is None:
            return self.origin
        return Origin(self.path, self.key_line(key), self.type_name, key)

    def error(self, key: str | None, reason: str) -> LaunchFileError:
        return LaunchFileError(self.origin_of(key), reason)

    # -- content -----------------------------------------------------------------------------
    @property
    def is_mapping(self) -> bool:
        return isinstance(self._body, dict)

    @property
    def keys(self) -> list[str]:
        return list(self._body) if isinstance(self._body, dict) else []

    def has(self, name: str) -> bool:
        self._asked.add(name)
        return isinstance(self._body, dict) and name in self._body

    @property
    def children(self) -> list['Entity']:
        """The child tags of `group`/`timer`: the bare list, or the mapping's `children:` list."""
        if isinstance(self._body, list):
            return _entities_from_list(self._body, self.path, parent=self)
        if isinstance(self._body, dict):
            return self.get_attr('children', data_type=list[Entity], optional=True, tags=True) or []
        return []

    def get_attr(self, name: str, *, data_type: Any = str, optional: bool = False,
                 tags: bool = False, can_be_str: bool = False) -> Any:
        """The value of attribute `name`, checked against `data_type`.

        Args:
            name: the YAML key.
            data_type: `str`, `int`, `float`, `bool`, `Scalar` (any scalar, as a string),
                `list[str]`, `list[int]` / `list[float]` / `list[bool]`, `list[Entity]` (a list of
                mappings), `Any` (unchecked); launch's `typing.List[...]` spellings are the same.
            optional: return None when the key is absent instead of raising.
            tags: with `list[Entity]`, items are one-key tag mappings (`children`) instead of
                attribute mappings (`remap: [{from: a, to: b}]`).
            can_be_str: a string is accepted whatever `data_type` asks for (launch's
                option, on by default there; off here, where a wrong type is an error).
        Raises:
            LaunchFileError: missing required key, or a value of the wrong type, naming the key.
        """
        data_type = normalized_type(data_type)
        self._asked.add(name)
        if not isinstance(self._body, dict):
            if optional:
                return None
            raise self.error(None, f"expected a mapping of attributes (with '{name}'), "
                                   f'got {_type_name(self._body)}')
        if name not in self._body:
            if optional:
                return None
            raise self.error(None, f"missing required attribute '{name}'")
        self._read.add(name)
        value = self._body[name]
        origin = Origin(self.path, self._body.value_lines.get(name, self.line)
                        if isinstance(self._body, YamlMap) else self.line, self.type_name, name)
        if data_type == list[Entity]:
            if isinstance(value, dict) and not tags:
                raise LaunchFileError(origin, f"expected a list of mappings, got a mapping: write "
                                              f"'{name}:' followed by '- ...' items")
            if not isinstance(value, list) or not all(isinstance(v, dict) for v in value):
                raise _wrong(origin, value, 'a list of mappings')
            if tags:
                return _entities_from_list(value, self.path, parent=self)
            lines = getattr(value, 'item_lines', [origin.line] * len(value))
            return [Entity(name, item, path=self.path, line=getattr(item, 'line', 0) or lines[i], parent=self)
                    for i, item in enumerate(value)]
        if can_be_str and isinstance(value, str):
            return value   # launch's option: text (with substitutions) stands for any type
        return checked_value(value, data_type, origin)

    def raw(self, name: str) -> Any:
        """The value of `name` without any check (None when absent); marks it as read."""
        self._asked.add(name)
        if isinstance(self._body, dict) and name in self._body:
            self._read.add(name)
            return self._body[name]
        return None

    def assert_entity_completely_parsed(self) -> None:
        """launch's name for `assert_complete()`, which `expose_action` calls after `parse`."""
        self.assert_complete()

    def assert_complete(self) -> None:
        """Raise for the first key that no parser read (an unknown or misspelled attribute)."""
        if not isinstance(self._body, dict):
            return
        unread = [key for key in self._body if key not in self._read]
        if unread:
            key = unread[0]
            known = sorted(self._asked)
            hint = f" (known keys: {', '.join(known)})" if known else ''
            raise LaunchFileError(self.origin_of(str(key)), f"unknown key '{key}' of `{self.type_name}`{hint}")


def _entities_from_list(items: list, path: str, *, parent: Entity | None) -> list[Entity]:
    """Tags from a YAML list: each item must be a one-key mapping `{tag: attributes}`."""
    lines = getattr(items, 'item_lines', None) or [getattr(items, 'line', 0)] * len(items)
    out = []
    for index, item in enumerate(items):
        line = lines[index] if index < len(lines) else 0
        where_tag = parent.type_name if parent is not None else 'launch'
        if not isinstance(item, dict) or len(item) != 1:
            what = (f'a mapping with {len(item)} keys ({", ".join(map(str, item))})'
                    if isinstance(item, dict) else _type_name(item))
            raise LaunchFileError(Origin(path, line, where_tag),
                                  f'each entry must be a mapping with exactly one key, the tag; got {what}')
        (tag, body), = item.items()
        if isinstance(item, YamlMap):
            line = item.key_lines.get(tag, line)
        if body is None:
            body = YamlMap()
            body.line, body.key_lines, body.value_lines = line, {}, {}
        out.append(Entity(str(tag), body, path=path, line=line, parent=parent))
    return out


def load_launch_entities(path: str | Path, text: str | None = None) -> list[Entity]:
    """The top-level tags of a launch file (`launch: [...]`)."""
    return load_launch_root(path, text).children


def load_launch_root(path: str | Path, text: str | None = None) -> Entity:
    """The `launch` entity of a YAML launch file, whose children are its top-level tags."""
    path = str(path)
    document = load_yaml(path, text)
    if not isinstance(document, dict) or 'launch' not in document:
        raise LaunchFileError(None, f"{path}:{getattr(document, 'line', 1) or 1}: "
                                    "a launch file must be a mapping with a 'launch:' list")
    extra = [k for k in document if k != 'launch']
    if extra:
        line = document.key_lines.get(extra[0], 1) if isinstance(document, YamlMap) else 1
        raise LaunchFileError(None, f"{path}:{line}: unknown top-level key '{extra[0]}' (only 'launch:')")
    body = document['launch']
    line = document.value_lines.get('launch', 1) if isinstance(document, YamlMap) else 1
    if body is None:
        body = YamlList()
    if not isinstance(body, list):
        raise LaunchFileError(None, f"{path}:{line}: 'launch:' must be a list of tags, got {_type_name(body)}")
    return Entity('launch', body, path=path, line=line)
