"""The package index: every package zros knows, and its share directory.

zros has no install space, so a package's share directory (what `share/<pkg>/` is in ROS 2,
holding `launch/`, `param/`, `map/`, `urdf/`, `rviz/`, ...) is a directory found here, first
match wins:
1. `<dir>/<pkg>/` under each `ZROS_NODE_PATH` directory (a package being worked on);
2. an installed Python package that declares itself with an entry point in the group
   `zros.packages` (`my_pkg = "my_pkg"`) or provides nodes in `zros.nodes`
   (`"my_pkg/my_node" = "my_pkg.my_node:main"`): the directory of that Python package;
3. `nodes/<pkg>/` shipped with zros (`demo_nodes`, `turtlesim`, the TurtleBot3 packages...);
4. `interfaces/<pkg>/` shipped with zros, and packages on `ZROS_INTERFACE_PATH` (message-only
   packages such as `std_msgs`);
5. `configs` (zros's example launch and parameter files) and `zros` (the directory above it).
A package's prefix is the directory that holds its share directory.
"""
from __future__ import annotations

import functools
import importlib.util
import os
import re
from pathlib import Path

from zros.errors import ZrosError

__all__ = ['PackageNotFoundError', 'get_package_share_directory', 'get_package_share_path',
           'get_package_prefix', 'get_packages_with_prefixes', 'package_directories',
           'interface_roots']

_KINDS = ('msg', 'srv', 'action')
_PACKAGE_NAME = re.compile(r'[A-Za-z][A-Za-z0-9_]*')


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
    for ep in metadata.entry_points(group='zros.packages'):
        folder = _module_directory(ep.value)
        if folder is not None:
            found.setdefault(ep.name, folder)
    for ep in metadata.entry_points(group='zros.nodes'):
        package = ep.name.split('/')[0]
        if package not in found and '.' in ep.module:
            folder = _module_directory(ep.module)
            if folder is not None:
                found[package] = folder
    return found


def _shipped_root(name: str) -> Path:
    import importlib
    module = importlib.import_module(name)   # namespace or regular package shipped with zros
    return Path(list(module.__path__)[0]).resolve()


def package_directories() -> dict[str, Path]:
    """Every package and its share directory, in lookup order (module docstring)."""
    found: dict[str, Path] = {}
    for root in _node_path_dirs():
        for name, folder in _package_dirs_under(root).items():
            found.setdefault(name, folder)
    for name, folder in _installed_packages().items():
        found.setdefault(name, folder)
    for name, folder in _package_dirs_under(_shipped_root('nodes')).items():
        found.setdefault(name, folder)
    from zros import typesupport
    for root in typesupport.search_roots():
        for name, folder in _package_dirs_under(root).items():
            if name not in found and any((folder / kind).is_dir() for kind in _KINDS):
                found[name] = folder
    configs = _shipped_root('configs')
    found.setdefault('configs', configs)
    found.setdefault('zros', configs.parent)
    return found


def interface_roots() -> list[Path]:
    """Directories laid out as `<pkg>/{msg,srv,action}` that hold the interfaces of packages
    on ZROS_NODE_PATH and of installed packages (for zros.typesupport's search path)."""
    roots: list[Path] = []
    candidates = [(name, folder) for root in _node_path_dirs() for name, folder in _package_dirs_under(root).items()]
    candidates += list(_installed_packages().items())
    for name, folder in candidates:
        if folder.name == name and any((folder / kind).is_dir() for kind in _KINDS) and folder.parent not in roots:
            roots.append(folder.parent)
    return roots


def get_package_share_path(package_name: str) -> Path:
    """The share directory of `package_name`; PackageNotFoundError when there is none."""
    folders = package_directories()
    folder = folders.get(package_name)
    if folder is None:
        raise PackageNotFoundError(f"package '{package_name}' not found (known: {', '.join(sorted(folders))}; "
                                   'see docs/packages.md)')
    return folder


def get_package_share_directory(package_name: str, print_warning: bool = True) -> str:
    """`get_package_share_directory('turtlebot3_gazebo')` as in ament_index_python."""
    return str(get_package_share_path(package_name))


def get_package_prefix(package_name: str) -> str:
    """The directory that holds the package's share directory."""
    return str(get_package_share_path(package_name).parent)


def get_packages_with_prefixes() -> dict[str, str]:
    return {name: str(folder.parent) for name, folder in package_directories().items()}
