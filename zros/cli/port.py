"""`zros port PATH...`: apply the rclpy -> zros porting edits to files or a package tree and
print what changed as a unified diff (zros.porting does the edits).

A directory is searched for `*.py` files (colcon's build/install/log directories, virtual
environments and hidden directories skipped). Notes about what zros lacks go to stderr as
`file:line: note`. `--dry-run` only prints the diff.
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

__all__ = ['add_arguments', 'cmd_port', 'python_files']

_SKIPPED_DIRS = {'build', 'install', 'log', '__pycache__', 'venv', 'node_modules'}


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument('paths', nargs='+', metavar='PATH', help='Python files or directories (a ROS 2 package)')
    parser.add_argument('-n', '--dry-run', action='store_true', help='print the diff, change no file')
    parser.set_defaults(handler=cmd_port)


def python_files(path: Path) -> list[Path]:
    """`path` itself, or the .py files under it (build output and environments skipped)."""
    if path.is_file():
        return [path]
    found = []
    for candidate in sorted(path.rglob('*.py')):
        relative = candidate.relative_to(path).parts[:-1]
        if not any(part.startswith('.') or part in _SKIPPED_DIRS or (Path(path, *relative[:i + 1]) / 'pyvenv.cfg').exists()
                   for i, part in enumerate(relative)):
            found.append(candidate)
    return found


def cmd_port(args: argparse.Namespace) -> int:
    import difflib

    from zros.errors import CliError
    from zros.porting import PortError, port_source
    paths = [Path(p) for p in args.paths]
    missing = [str(p) for p in paths if not p.exists()]
    if missing:
        raise CliError(f"no such file or directory: {', '.join(missing)}")
    changed = failed = 0
    for path in [f for p in paths for f in python_files(p)]:
        try:
            original = path.read_text(encoding='utf-8')
            ported, notes = port_source(original, str(path))
        except (OSError, UnicodeDecodeError) as exc:
            print(f'zros port: cannot read {path}: {exc}', file=sys.stderr)
            failed += 1
            continue
        except PortError as exc:
            print(f'zros port: {exc}', file=sys.stderr)
            failed += 1
            continue
        for note in notes:
            print(f'{path}:{note.line}: {note.text}', file=sys.stderr)
        if ported == original:
            continue
        changed += 1
        old_name, new_name = (str(path), str(path)) if path.is_absolute() else (f'a/{path}', f'b/{path}')
        sys.stdout.writelines(difflib.unified_diff(original.splitlines(keepends=True), ported.splitlines(keepends=True),
                                                   old_name, new_name))
        if not args.dry_run:
            path.write_text(ported, encoding='utf-8')
    verb = 'would port' if args.dry_run else 'ported'
    print(f'zros port: {verb} {changed} file(s)' + (f', {failed} could not be read' if failed else ''),
          file=sys.stderr)
    return 1 if failed else 0
