"""Count which public names of zros's user-facing API carry a docstring.

Editors show a name's docstring on hover, and users learn the rclpy-shaped API from it, so the
modules users import are held to a coverage target (issue 40: at least 90 %). The count is
ast-based, so it runs without importing zros (no Zenoh session, no optional dependencies).

Public means no leading underscore: module-level functions and classes, and the methods and
properties of public classes (a property's setter counts with its getter, once). Dunder methods
are private by that rule.

    python tools/docstring_coverage.py                 # the table for the public-API modules
    python tools/docstring_coverage.py --fail-under 90 # exit 1 below 90 % overall
    python tools/docstring_coverage.py --missing       # also list the undocumented names
    python tools/docstring_coverage.py zros/foo.py     # any other files
"""
from __future__ import annotations

import argparse
import ast
import sys
from pathlib import Path
from typing import Iterator, NamedTuple

ROOT = Path(__file__).resolve().parent.parent

# The modules users import (issue 40, item 4), relative to the repository root.
PUBLIC_API_MODULES = (
    'zros/node.py', 'zros/publisher.py', 'zros/subscription.py', 'zros/client.py', 'zros/service.py',
    'zros/timer.py', 'zros/executors.py', 'zros/action/client.py', 'zros/action/server.py',
    'zros/parameter.py', 'zros/time.py', 'zros/duration.py', 'zros/clock.py', 'zros/qos.py',
    'zros/task.py', 'zros/callback_groups.py', 'zros/tf2_ros/buffer.py', 'zros/tf2_ros/buffer_core.py',
    'zros/tf2_ros/transform_listener.py', 'zros/tf2_ros/transform_broadcaster.py',
    'zros/tf2_ros/static_transform_broadcaster.py', 'zros/lifecycle/node.py',
    'zros/nav2_simple_commander/robot_navigator.py',
)


class PublicName(NamedTuple):
    """One public definition: its dotted name within the module and whether it has a docstring."""
    qualname: str
    documented: bool


def _is_public(name: str) -> bool:
    return not name.startswith('_')


def _is_accessor(node: ast.FunctionDef | ast.AsyncFunctionDef) -> bool:
    """A `@x.setter` / `@x.deleter` belongs to the property `x`, counted once with its getter."""
    return any(isinstance(d, ast.Attribute) and d.attr in ('setter', 'deleter') for d in node.decorator_list)


def public_names(tree: ast.Module) -> Iterator[PublicName]:
    """Yield the public functions, classes and (for public classes) methods of a parsed module."""
    for node in tree.body:
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)) and _is_public(node.name):
            yield PublicName(node.name, ast.get_docstring(node) is not None)
        elif isinstance(node, ast.ClassDef) and _is_public(node.name):
            yield PublicName(node.name, ast.get_docstring(node) is not None)
            for member in node.body:
                if (isinstance(member, (ast.FunctionDef, ast.AsyncFunctionDef)) and _is_public(member.name)
                        and not _is_accessor(member)):
                    yield PublicName(f'{node.name}.{member.name}', ast.get_docstring(member) is not None)


def module_names(path: Path) -> list[PublicName]:
    """The public names of the Python file at `path`."""
    return list(public_names(ast.parse(path.read_text(), filename=str(path))))


def main(paths: list[Path], fail_under: float | None, show_missing: bool) -> int:
    """Print a per-module table; return the exit status (1 when below `fail_under` percent)."""
    rows = []
    for path in paths:
        names = module_names(path)
        rows.append((path, sum(n.documented for n in names), len(names), names))
    width = max(len(_display(p)) for p, *_ in rows)
    print(f"{'module':<{width}}  documented  total  coverage")
    for path, documented, total, names in rows:
        print(f'{_display(path):<{width}}  {documented:>10}  {total:>5}  {_percent(documented, total):>7.1f}%')
        if show_missing:
            for name in names:
                if not name.documented:
                    print(f'    missing: {name.qualname}')
    documented = sum(r[1] for r in rows)
    total = sum(r[2] for r in rows)
    overall = _percent(documented, total)
    print(f"{'all':<{width}}  {documented:>10}  {total:>5}  {overall:>7.1f}%")
    if fail_under is not None and overall < fail_under:
        print(f'docstring coverage {overall:.1f}% is below {fail_under:g}%', file=sys.stderr)
        return 1
    return 0


def _display(path: Path) -> str:
    try:
        return str(path.resolve().relative_to(ROOT))
    except ValueError:
        return str(path)


def _percent(part: int, whole: int) -> float:
    return 100.0 * part / whole if whole else 100.0


if __name__ == '__main__':
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('files', nargs='*', type=Path,
                        help='Python files to count (default: the public-API modules)')
    parser.add_argument('--fail-under', type=float, metavar='PERCENT',
                        help='exit 1 when overall coverage is below PERCENT')
    parser.add_argument('--missing', action='store_true', help='list the names without a docstring')
    args = parser.parse_args()
    files = args.files or [ROOT / m for m in PUBLIC_API_MODULES]
    for file in files:
        if not file.is_file():
            parser.exit(2, f'docstring_coverage: {file}: no such file\n')
    sys.exit(main(files, args.fail_under, args.missing))
