"""`zros env WS`: the shell exports that make a workspace's packages visible, zros's answer to
`source install/setup.bash`.

    eval "$(zros env ~/ros2_ws)"

There is nothing to build, so "sourcing" a workspace only means adding its directories to the
two search paths: `ZROS_INTERFACE_PATH` (directories holding `<pkg>/msg|srv|action/`) and
`ZROS_NODE_PATH` (directories holding `<pkg>/<executable>.py`). Packages are looked for in
`WS/src/` when it exists (a colcon workspace), else in `WS/` itself. A ROS package (a folder with
`package.xml`, as `ros2 pkg create` makes it) is read in place from there, setup.py's console
scripts and data files included (zros.ament_index_python.ros_packages); a folder without one that
holds `my_pkg/my_pkg/node.py` contributes `src/my_pkg` so that `zros run my_pkg node` finds it.
What the variables held before is kept after the new directories, without duplicates.
"""
from __future__ import annotations

import argparse
import json
import os
import shlex
from pathlib import Path

__all__ = ['add_arguments', 'workspace_paths']

_INTERFACE_DIRS = ('msg', 'srv', 'action')


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument('workspace', nargs='?', default='.', help='the workspace directory (default: .)')
    parser.add_argument('--json', action='store_true', help='print {"ZROS_INTERFACE_PATH": [...], "ZROS_NODE_PATH": [...]}')
    parser.set_defaults(handler=cmd_env)


def _packages(root: Path) -> list[Path]:
    return sorted(p for p in root.iterdir() if p.is_dir() and not p.name.startswith(('.', '_')))


def workspace_paths(workspace: str | os.PathLike[str]) -> dict[str, list[str]]:
    """{'ZROS_INTERFACE_PATH': [dirs], 'ZROS_NODE_PATH': [dirs]} for the workspace's packages.

    Raises:
        CliError: the workspace does not exist or holds no package zros can use.
    """
    from zros.errors import CliError
    base = Path(workspace).expanduser().resolve()
    if not base.is_dir():
        raise CliError(f"workspace '{workspace}' is not a directory")
    root = base / 'src' if (base / 'src').is_dir() else base
    interfaces: list[str] = []
    nodes: list[str] = []
    for package in _packages(root):
        if any((package / kind).is_dir() for kind in _INTERFACE_DIRS) and str(root) not in interfaces:
            interfaces.append(str(root))
        if (package / 'package.xml').is_file():    # a ROS package: read in place from its folder
            if str(root) not in nodes:
                nodes.append(str(root))
            continue
        if any(package.glob('*.py')) and str(root) not in nodes:
            nodes.append(str(root))
        module = package / package.name          # ament_python: src/my_pkg/my_pkg/*.py
        if module.is_dir() and any(module.glob('*.py')):
            nodes.append(str(package))
    if not interfaces and not nodes:
        raise CliError(f"no packages in '{root}': expected <pkg>/msg|srv|action/ or <pkg>/<executable>.py")
    return {'ZROS_INTERFACE_PATH': interfaces, 'ZROS_NODE_PATH': nodes}


def cmd_env(args: argparse.Namespace) -> int:
    paths = workspace_paths(args.workspace)
    if args.json:
        print(json.dumps(paths))
        return 0
    for variable, dirs in paths.items():
        if not dirs:
            continue
        old = [d for d in os.environ.get(variable, '').split(os.pathsep) if d and d not in dirs]
        print(f'export {variable}={shlex.quote(os.pathsep.join(dirs + old))}')
    return 0
