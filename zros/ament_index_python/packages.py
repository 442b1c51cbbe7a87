"""The package index: every package zros knows, and its share directory.

zros has no install space, so a package's share directory (what `share/<pkg>/` is in ROS 2,
holding `launch/`, `param/`, `map/`, `urdf/`, `rviz/`, ...) is a directory found here, first
match wins:
1. under each `ZROS_NODE_PATH` directory (a package being worked on):
   a. `<dir>/<pkg>/`; when `<dir>` is a Python project (a `pyproject.toml`, as `zros pkg create`
      writes), only the packages its `zros.packages` / `zros.nodes` entry points name, as
      `pip install -e <dir>` would make them (its `tests/`, `docs/`, ... are no packages);
   b. ROS packages in source (a folder with `package.xml`: a colcon workspace, its `src/`, or the
      package itself), found and read as colcon would (zros.ament_index_python.ros_packages);
2. installed packages:
   a. a Python package that declares itself with an entry point in the group `zros.packages`
      (`my_pkg = "my_pkg"`) or provides nodes in `zros.nodes` (`"my_pkg/my_node" =
      "my_pkg.my_node:main"`): the directory of that Python package;
   b. a ROS package installed with `pip install -e` (read from its source, as 1b);
   c. the ament resource index of each `AMENT_PREFIX_PATH` directory, then of this Python
      environment (a non-editable `pip install` of an ament_python package);
3. `nodes/<pkg>/` shipped with zros (`demo_nodes`, `turtlesim`, the TurtleBot3 packages...);
4. `interfaces/<pkg>/` shipped with zros, and packages on `ZROS_INTERFACE_PATH` (message-only
   packages such as `std_msgs`);
5. `configs` (zros's example launch and parameter files) and `zros` (the directory above it).
A zros package folder's prefix is the directory that holds it; a ROS package's is the directory
holding `share/<pkg>`. The executables of packages found by 1a and 3 are the `*.py` files in
their folder (`IndexEntry.scripts`); those of 2a are their `zros.nodes` entry points; those
of ROS packages are their `console_scripts` and `lib/<pkg>/` files (`ros_packages`);
zros.ament_index_python.executables lists and loads them.
"""
from __future__ import annotations

import functools
import importlib.util
import os
import re
import sys
from pathlib import Path
from typing import NamedTuple

from zros.ament_index_python.ros_packages import (RosPackage, SetupPyError, editable_source_dirs,
                                                  find_source_packages, prefix_packages, source_package)
from zros.errors import ZrosError, with_suggestion

__all__ = ['PackageNotFoundError', 'get_package_share_directory', 'get_package_share_path',
           'get_package_prefix', 'get_packages_with_prefixes', 'package_directories',
           'ros_packages', 'interface_roots', 'IndexEntry', 'package_index']

_KINDS = ('msg', 'srv', 'action')
_PACKAGE_NAME = re.compile(r'[A-Za-z][A-Za-z0-9_]*')


class IndexEntry(NamedTuple):
    """What the package index knows of one package (module docstring)."""
    share: Path                       # its share directory
    scripts: Path | None              # the folder whose `*.py` files are its executables
    ros_package: RosPackage | None    # its ROS package record (executables, prefix)
    module: str | None                # the Python package `scripts` imports as (shipped nodes)


class PackageNotFoundError(ZrosError, KeyError):
    """No package of that name (a KeyError, as ament_index_python's)."""

    def __str__(self) -> str:
        return str(self.args[0]) if self.args else ''


def _package_dirs_under(root: Path) -> dict[str, Path]:
    if not root.is_dir():
        return {}
    return {p.name: p.resolve() for p in sorted(root.iterdir()) if p.is_dir() and _PACKAGE_NAME.fullmatch(p.name)}


def _node_path_dirs() -> list[Path]:
    return [Path(p) for p in os.environ.get('ZROS_NODE_PATH', '').split(os.pathsep) if p]


def _entry_point_packages(entry_points: dict) -> dict[str, str]:
    """{package: top-level module} named by a project's `zros.packages` and `zros.nodes` entry
    points (`{group: {name: 'module[:function]'}}`)."""
    found: dict[str, str] = {}
    for name, module in entry_points.get('zros.packages', {}).items():
        found.setdefault(name, module.split('.')[0])
    for name, target in entry_points.get('zros.nodes', {}).items():
        module = target.split(':')[0]
        if '.' in module:   # a package's module, not a lone top-level script
            found.setdefault(name.split('/')[0], module.split('.')[0])
    return found


def _project_packages(root: Path) -> dict[str, Path] | None:
    """The packages a Python project folder declares, or None when `root` holds no
    pyproject.toml with zros entry points (then each subfolder is a package)."""
    import tomllib
    try:
        with open(root / 'pyproject.toml', 'rb') as handle:
            entry_points = tomllib.load(handle).get('project', {}).get('entry-points', {})
    except (OSError, tomllib.TOMLDecodeError):
        return None
    declared = _entry_point_packages(entry_points)
    if not declared:
        return None
    return {name: (root / module).resolve() for name, module in sorted(declared.items()) if (root / module).is_dir()}


def _node_path_layout() -> tuple[list[tuple[str, Path]], list[Path]]:
    """What the directories of ZROS_NODE_PATH hold, in order (module docstring, 1.): the
    zros-style package folders as (package, folder) (1a), and the source folders of ROS packages,
    those with a package.xml (1b). Each directory is read once."""
    folders: list[tuple[str, Path]] = []
    ros_folders: list[Path] = []
    for root in _node_path_dirs():
        declared = _project_packages(root)
        if declared is None:
            found = find_source_packages(root)
            declared = {name: folder for name, folder in _package_dirs_under(root).items()
                        if not any(folder == ros or folder in ros.parents for ros in found)}
            ros_folders.extend(found)
        folders.extend(declared.items())
    return folders, ros_folders


_warned: set[str] = set()


def _source_packages(folders: list[Path]) -> list[RosPackage]:
    """The ROS packages in these source folders; one whose package.xml or setup.py cannot be
    read is left out, with one warning line."""
    packages = []
    for folder in folders:
        try:
            packages.append(source_package(folder))
        except SetupPyError as exc:
            if str(exc) not in _warned:
                _warned.add(str(exc))
                print(f'[WARN] [zros]: package skipped: {exc}', file=sys.stderr)
    return packages


def _module_directory(module: str) -> Path | None:
    """The directory of a top-level Python package, found without importing it."""
    try:
        spec = importlib.util.find_spec(module.split('.')[0])
    except (ImportError, ValueError):
        return None
    if spec is None or not spec.submodule_search_locations:
        return None
    return Path(list(spec.submodule_search_locations)[0]).resolve()


@functools.lru_cache(maxsize=1)
def _installed_packages() -> dict[str, Path]:
    """Packages installed with entry points (read once per process: installing one is a new
    process's business)."""
    from importlib import metadata
    found: dict[str, Path] = {}
    declared = _entry_point_packages({group: {ep.name: ep.value for ep in metadata.entry_points(group=group)}
                                      for group in ('zros.packages', 'zros.nodes')})
    for name, module in declared.items():
        folder = _module_directory(module)
        if folder is not None:
            found[name] = folder
    return found


def _shipped_root(name: str) -> Path:
    import importlib
    module = importlib.import_module(name)   # namespace or regular package shipped with zros
    return Path(list(module.__path__)[0]).resolve()


def package_index() -> dict[str, IndexEntry]:
    """Every package the index finds, in lookup order (module docstring). Each call reads the
    directories afresh (a package may appear while a launch runs): read it once per question.

    A ROS package in source whose nodes are compiled (ament_cmake: a fetched slam_toolbox or
    turtlebot3_gazebo) has no executables zros can run; when zros ships a package of that
    name, its nodes stand in, and the share directory stays the source's.
    """
    found: dict[str, IndexEntry] = {}
    node_path_folders, node_path_sources = _node_path_layout()
    for name, folder in node_path_folders:
        found.setdefault(name, IndexEntry(folder, folder, None, None))
    for package in _source_packages(node_path_sources):
        found.setdefault(package.name, IndexEntry(package.share, None, package, None))
    for name, folder in _installed_packages().items():
        found.setdefault(name, IndexEntry(folder, None, None, None))
    for package in _source_packages(editable_source_dirs()) + prefix_packages():
        found.setdefault(package.name, IndexEntry(package.share, None, package, None))
    for name, folder in _package_dirs_under(_shipped_root('nodes')).items():
        if name not in found:
            found[name] = IndexEntry(folder, folder, None, f'nodes.{name}')
        elif found[name].ros_package is not None and found[name].ros_package.compiled:
            # zros's nodes stand in for compiled ones
            found[name] = found[name]._replace(scripts=folder, module=f'nodes.{name}')
    from zros import typesupport
    for root in typesupport.search_roots():
        for name, folder in _package_dirs_under(root).items():
            if name not in found and any((folder / kind).is_dir() for kind in _KINDS):
                found[name] = IndexEntry(folder, None, None, None)
    configs = _shipped_root('configs')
    found.setdefault('configs', IndexEntry(configs, None, None, None))
    found.setdefault('zros', IndexEntry(configs.parent, None, None, None))
    return found


def ros_packages() -> dict[str, RosPackage]:
    """The packages of the index that are ROS packages (package.xml in source, or an install
    prefix's ament index), with their executables (zros.ament_index_python.ros_packages)."""
    return {name: entry.ros_package for name, entry in package_index().items() if entry.ros_package is not None}


def package_directories() -> dict[str, Path]:
    """Every package and its share directory, in lookup order (module docstring)."""
    return {name: entry.share for name, entry in package_index().items()}


def interface_roots() -> list[Path]:
    """Directories laid out as `<pkg>/{msg,srv,action}` that hold the interfaces of packages
    on ZROS_NODE_PATH (ROS packages in source among them: a workspace's interface package) and
    of installed packages (for zros.typesupport's search path)."""
    roots: list[Path] = []
    folders, sources = _node_path_layout()
    sources = sources + editable_source_dirs()
    candidates = folders + [(f.name, f.resolve()) for f in sources] + list(_installed_packages().items())
    for name, folder in candidates:
        if folder.name == name and any((folder / kind).is_dir() for kind in _KINDS) and folder.parent not in roots:
            roots.append(folder.parent)
    return roots


def get_package_share_path(package_name: str) -> Path:
    """The share directory of `package_name`; PackageNotFoundError when there is none."""
    folders = package_directories()
    folder = folders.get(package_name)
    if folder is None:
        raise PackageNotFoundError(with_suggestion(
            f"package '{package_name}' not found", package_name, folders,
            otherwise=f" (known: {', '.join(sorted(folders))}; see docs/packages.md)"))
    return folder


def get_package_share_directory(package_name: str, print_warning: bool = True) -> str:
    """`get_package_share_directory('turtlebot3_gazebo')` as in ament_index_python."""
    return str(get_package_share_path(package_name))


def _prefix(share: Path, package: RosPackage | None) -> Path:
    return package.prefix if package is not None else share.parent


def get_package_prefix(package_name: str) -> str:
    """The package's install prefix: for a ROS package the directory holding `share/<pkg>`, for
    a zros package folder the directory that holds it."""
    share = get_package_share_path(package_name)
    return str(_prefix(share, ros_packages().get(package_name)))


def get_packages_with_prefixes() -> dict[str, str]:
    return {name: str(_prefix(entry.share, entry.ros_package)) for name, entry in package_index().items()}
