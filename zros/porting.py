"""The porting edits that turn rclpy code into zros code, on source text (`zros port` writes them).

Only imports and the name `rclpy` change; everything else, comments and layout included, stays:
- `import rclpy` / `rclpy.x` -> `import zros` / `zros.x` (every `rclpy` name in the code);
- `from std_msgs.msg import String` -> `from interfaces.std_msgs.msg import String`;
- `from tf2_ros import Buffer` -> `from zros.tf2_ros import Buffer`, `import tf2_ros` ->
  `from zros import tf2_ros` (the name the code uses stays bound);
- ROS 1's `sensor_msgs.point_cloud2` -> `zros.sensor_msgs_py.point_cloud2`.
The rule itself is zros.import_hook.module_target, shared with `zros python`.
"""
from __future__ import annotations

import ast
import io
import sys
import tokenize
from typing import NamedTuple

from zros.errors import ZrosError
from zros.import_hook import module_target

__all__ = ['port_source', 'PortError', 'Note']


class PortError(ZrosError):
    """The source cannot be parsed as Python."""


class Note(NamedTuple):
    """Something the port could not settle by itself, at a line of the ported file."""
    line: int
    text: str


def _stdlib(top: str) -> bool:
    return top in sys.stdlib_module_names


def _target(name: str) -> str | None:
    return module_target(name, _stdlib)


def port_source(text: str, filename: str = '<source>') -> tuple[str, list[Note]]:
    """The ported text and the notes about it.

    Raises:
        PortError: the text is not valid Python.
    """
    try:
        tree = ast.parse(text, filename)
        tokens = list(tokenize.generate_tokens(io.StringIO(text).readline))
    except (SyntaxError, tokenize.TokenError) as exc:
        line = getattr(exc, 'lineno', None) or (exc.args[1][0] if len(exc.args) > 1 else 0)
        raise PortError(f'{filename}:{line}: cannot parse: {exc.args[0]}') from None
    offsets = _line_offsets(text)
    edits: list[tuple[int, int, str]] = []
    taken: list[tuple[int, int]] = []
    notes: list[Note] = []
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            target = _target(node.module)
            if target:
                start, end = _module_span(tokens, offsets, node)
                edits.append((start, end, target))
                notes.extend(_check(target, node.lineno))
            taken.append(_span(offsets, node))
        elif isinstance(node, ast.Import):
            replacement = _import_statement(node, offsets, text, notes)
            if replacement is not None:
                edits.append((*_span(offsets, node), replacement))
            taken.append(_span(offsets, node))
    for token in tokens:
        if token.type == tokenize.NAME and token.string == 'rclpy':
            at = offsets[token.start[0] - 1] + token.start[1]
            if not any(start <= at < end for start, end in taken):
                edits.append((at, at + len('rclpy'), 'zros'))
    for start, end, replacement in sorted(edits, reverse=True):
        text = text[:start] + replacement + text[end:]
    return text, sorted(set(notes))


def _line_offsets(text: str) -> list[int]:
    offsets, total = [], 0
    for line in text.splitlines(keepends=True):
        offsets.append(total)
        total += len(line)
    offsets.append(total)
    return offsets


def _span(offsets: list[int], node: ast.stmt) -> tuple[int, int]:
    return (offsets[node.lineno - 1] + node.col_offset, offsets[node.end_lineno - 1] + node.end_col_offset)


def _module_span(tokens: list[tokenize.TokenInfo], offsets: list[int], node: ast.ImportFrom) -> tuple[int, int]:
    """Where the dotted module name of a `from M import ...` statement is in the text."""
    start = (node.lineno, node.col_offset)
    inside = [t for t in tokens if t.start >= start]
    first = next(i for i, t in enumerate(inside) if t.type == tokenize.NAME and t.string == 'from') + 1
    last = first
    while inside[last + 1].string == '.' and inside[last + 2].type == tokenize.NAME:
        last += 2
    (line_a, col_a), (line_b, col_b) = inside[first].start, inside[last].end
    return offsets[line_a - 1] + col_a, offsets[line_b - 1] + col_b


def _import_statement(node: ast.Import, offsets: list[int], text: str, notes: list[Note]) -> str | None:
    """`import a.b [as c], ...` rewritten so that every name the code uses stays bound."""
    lines, changed = [], False
    for alias in node.names:
        target = _target(alias.name)
        if target is None:
            lines.append(f'import {alias.name}' + (f' as {alias.asname}' if alias.asname else ''))
            continue
        changed = True
        notes.extend(_check(target, node.lineno))
        head = alias.name.split('.')[0]
        if alias.asname:
            lines.append(f'import {target} as {alias.asname}')
        elif head == 'rclpy':
            lines.append(f'import {target}')  # and every `rclpy` name becomes `zros`
        elif '.' not in alias.name:
            package, _, name = target.rpartition('.')
            lines.append(f'from {package} import {name}')
        elif target.endswith(alias.name):  # import X.y -> import zros.X.y; from zros import X
            lines.append(f'import {target}')
            lines.append(f'from {target[:-len(alias.name) - 1]} import {head}')
        else:
            lines.append(f'import {target} as {alias.name.rpartition(".")[2]}')
            notes.append(Note(node.lineno, f"'{alias.name}' is now '{alias.name.rpartition('.')[2]}': "
                                           'edit the code that names it in full'))
    if not changed:
        return None
    indent = text[offsets[node.lineno - 1]:offsets[node.lineno - 1] + node.col_offset]
    return ('\n' + indent).join(lines)


def _check(target: str, line: int) -> list[Note]:
    """Notes for a target that zros does not have (yet)."""
    import importlib.util
    parts = target.split('.')
    if parts[0] == 'interfaces':
        from zros.typesupport import list_packages
        if parts[1] not in list_packages():
            return [Note(line, f"zros ships no '{parts[1]}' interfaces: put its msg/srv/action files in a "
                               'directory named on ZROS_INTERFACE_PATH')]
        return []
    try:
        found = importlib.util.find_spec(target) is not None
    except (ImportError, ValueError):
        found = False
    return [] if found else [Note(line, f"'{target}' does not exist in this zros (yet)")]
