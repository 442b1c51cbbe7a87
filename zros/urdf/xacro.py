"""xacro, as the ROS tool, through the `xacro` package from PyPI (ROS's own xacro, pure Python).

The one piece of ROS it needs is `$(find pkg)`, which upstream resolves through
ament_index_python; here it resolves through zros's package lookup (the share directory of a
package under `nodes/` or `ZROS_NODE_PATH`), so course xacro files expand unchanged. Errors
become one line naming the file (and macro) being processed, instead of upstream's several
lines or, for a missing file, a traceback.

    zros.urdf.xacro.process_file('robot.urdf.xacro', {'prefix': 'left_'})   # -> URDF text
    $ xacro robot.urdf.xacro prefix:=left_ > robot.urdf                     # the same, shell
"""
from __future__ import annotations

import os
import sys
import xml.parsers.expat
from pathlib import Path
from typing import Mapping

from zros.errors import ZrosError

__all__ = ['XacroError', 'process_file', 'main']


class XacroError(ZrosError):
    """A xacro file that cannot be expanded; the message starts with the file at fault."""


def _find_package(package: str) -> str:
    from zros.ament_index_python.packages import get_package_share_directory
    return get_package_share_directory(package)


def _use_zros_packages() -> None:
    import xacro.substitution_args
    xacro.substitution_args._eval_find = _find_package


def _where() -> str:
    import xacro
    files = [f for f in (xacro.filestack or []) if f]
    macros = [m.body.getAttribute('name') for m in (xacro.macrostack or [])]
    where = str(files[-1]) if files else 'xacro'
    return where + (f" (in macro '{macros[-1]}')" if macros else '')


def process_file(path: str | Path, mappings: Mapping[str, str] | None = None) -> str:
    """Expand the xacro file at `path` with `name:=value` arguments `mappings`; the URDF text.

    Raises:
        XacroError: `file: reason` for unknown macros, bad expressions, missing includes,
        unknown packages and malformed XML.
    """
    import xacro
    _use_zros_packages()
    try:
        doc = xacro.process_file(str(path), mappings=dict(mappings or {}))
    except xml.parsers.expat.ExpatError as exc:
        raise XacroError(f'{_where()}: XML parsing error: {exc}') from None
    except Exception as exc:  # noqa: BLE001 - xacro raises many kinds; each becomes one line
        text = str(exc) or repr(exc)
        raise XacroError(f'{_where()}: {" ".join(text.split())}') from None
    return doc.toprettyxml(indent='  ')


def main(argv: list[str] | None = None) -> int:
    """The `xacro` command: `xacro FILE [name:=value ...] [-o OUT]`, as ROS's."""
    import xacro
    from xacro.cli import process_args
    argv = list(sys.argv[1:] if argv is None else argv)
    options, input_file = process_args(argv)
    if options.root_dir:
        xacro.root_dir = options.root_dir
    try:
        text = process_file(input_file, options.mappings)
    except XacroError as exc:
        print(f'xacro: error: {exc}', file=sys.stderr)
        return 2
    if options.just_deps:
        text = ' '.join(sorted(set(xacro.all_includes)))
    if options.output:
        Path(options.output).write_text(text)
    else:
        sys.stdout.write(text)
    return 0


def entry_point() -> None:
    try:
        sys.exit(main())
    except BrokenPipeError:
        os._exit(0)
