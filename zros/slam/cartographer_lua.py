"""Cartographer's Lua configuration files (`-configuration_directory DIR -configuration_basename
turtlebot3_lds_2d.lua`), read for zros's SLAM in Cartographer's place.

Cartographer's configurations are Lua programs of one shape: `include "other.lua"`, an
`options = { key = value, ... }` table, assignments to dotted names
(`TRAJECTORY_BUILDER_2D.max_range = 3.5`), `math.rad(x)`, and `return options`. This reads that
shape, no more: values are strings, numbers, booleans or nested tables; a name that refers to
another table (`map_builder = MAP_BUILDER`) reads as None. Includes are read from the same
directory when there; Cartographer's own defaults (`map_builder.lua`, ...) are not shipped, so
a missing include is skipped. `slam_parameters` maps what has a counterpart onto zros.slam's
parameter names.
"""
from __future__ import annotations

import math
import re
from pathlib import Path
from typing import Any

__all__ = ['LuaConfigError', 'read_options', 'slam_parameters']

_TOKEN = re.compile(r'''\s*(?:(--[^\n]*)|("(?:[^"\\]|\\.)*"|'(?:[^'\\]|\\.)*')|
                       ([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)|([A-Za-z_][\w.]*)|(.))''', re.X)


class LuaConfigError(ValueError):
    """A configuration that is not of the shape this reader knows; the message names file and line."""


class _Reader:
    def __init__(self, text: str, path: str) -> None:
        self.tokens: list[tuple[str, str, int]] = []   # (kind, text, line)
        for match in _TOKEN.finditer(text):
            comment, string, number, name, other = match.groups()
            line = text.count('\n', 0, match.end() - len(match.group(0).lstrip())) + 1
            if string is not None:
                self.tokens.append(('str', string[1:-1], line))
            elif number is not None:
                self.tokens.append(('num', number, line))
            elif name is not None:
                self.tokens.append(('name', name, line))
            elif other is not None and not other.isspace():
                self.tokens.append(('op', other, line))
        self.i, self.path = 0, path

    def peek(self) -> tuple[str, str, int] | None:
        return self.tokens[self.i] if self.i < len(self.tokens) else None

    def take(self, text: str | None = None) -> tuple[str, str, int]:
        token = self.peek()
        if token is None or (text is not None and token[1] != text):
            where = token[2] if token else (self.tokens[-1][2] if self.tokens else 1)
            raise LuaConfigError(f"{self.path}:{where}: expected {text or 'a value'!r}, got "
                                 f"{token[1] if token else 'the end of the file'!r}")
        self.i += 1
        return token

    def value(self) -> Any:
        kind, text, line = self.take()
        if kind == 'str':
            return text
        if kind == 'num':
            return float(text) if any(c in text for c in '.eE') else int(text)
        if text == '{':
            return self.table()
        if text == '-':
            return -self.value()
        if kind == 'name':
            if text in ('true', 'false'):
                return text == 'true'
            if text == 'nil':
                return None
            if text == 'math.rad':
                self.take('(')
                degrees = self.value()
                self.take(')')
                return math.radians(degrees)
            return None   # a reference to another table (MAP_BUILDER)
        raise LuaConfigError(f'{self.path}:{line}: unexpected {text!r}')

    def table(self) -> dict:
        table: dict[str, Any] = {}
        while self.peek() is not None and self.peek()[1] != '}':
            key = self.take()[1]
            self.take('=')
            table[key] = self.value()
            if self.peek() is not None and self.peek()[1] in (',', ';'):
                self.take()
        self.take('}')
        return table


def read_options(path: str | Path, _seen: frozenset = frozenset()) -> dict[str, Any]:
    """{dotted name: value} of a Cartographer configuration: the `options` table's entries under
    their own names (`map_frame`) and every dotted assignment (`TRAJECTORY_BUILDER_2D.max_range`).

    Raises:
        LuaConfigError: the file is missing or not of the known shape (one line: file and line).
    """
    path = Path(path)
    try:
        text = path.read_text(encoding='utf-8')
    except OSError as exc:
        raise LuaConfigError(f'{path}: cannot read: {exc.strerror}') from None
    reader = _Reader(text, str(path))
    found: dict[str, Any] = {}
    while reader.peek() is not None:
        kind, word, line = reader.take()
        if word == 'include':
            name = reader.take()[1]
            included = path.parent / name
            if included.is_file() and included not in _seen:
                found.update(read_options(included, _seen | {path}))
        elif word == 'return':
            reader.take()
        elif kind == 'name':
            reader.take('=')
            value = reader.value()
            if word == 'options' and isinstance(value, dict):
                found.update(value)
            else:
                found[word] = value
        else:
            raise LuaConfigError(f'{path}:{line}: unexpected {word!r}')
    return found


def slam_parameters(options: dict[str, Any]) -> dict[str, Any]:
    """zros.slam / slam node parameters for what has a counterpart in Cartographer's options."""
    names = {
        'map_frame': 'map_frame',
        'odom_frame': 'odom_frame',
        'TRAJECTORY_BUILDER_2D.max_range': 'max_laser_range',
        'TRAJECTORY_BUILDER_2D.missing_data_ray_length': 'missing_data_ray_length',
        'lookup_transform_timeout_sec': 'transform_timeout',
    }
    found = {}
    for theirs, ours in names.items():
        value = options.get(theirs)
        if value is not None:
            found[ours] = value if isinstance(value, str) else float(value)
    return found
