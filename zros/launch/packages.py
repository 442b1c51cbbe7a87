"""Where packages live, for `$(find-pkg-share PKG)` and `zros launch PKG FILE`.

zros has no colcon install space, so "share directory" is defined here:
- a node package (`zros run PKG ...`: `nodes/PKG/` shipped with zros, or `PKG/` under a
  `ZROS_NODE_PATH` directory) -> that package's directory;
- `configs` -> the `configs/` directory shipped with zros (launch files, parameter files);
- `zros` -> the directory that holds `configs/`, so `$(find-pkg-share zros)/configs/x.yaml`
  and `$(find-pkg-share configs)/x.yaml` name the same file.
A launch file given as `zros launch PKG FILE` is looked up in the share directory and then in
its `launch/` subdirectory, except that for `zros` the directory is `configs/`.
"""
from __future__ import annotations

from pathlib import Path

from zros.launch.errors import LaunchError

__all__ = ['PackageNotFoundError', 'package_share_directory', 'configs_directory', 'find_launch_file',
           'known_packages']


class PackageNotFoundError(LaunchError):
    """No zros package of that name."""


def configs_directory() -> Path:
    """The `configs/` directory shipped with zros (a namespace package, so it has no __file__)."""
    import configs
    return Path(list(configs.__path__)[0]).resolve()


def _node_package_directory(package: str) -> Path | None:
    from zros.cli.run import _builtin_nodes_dir, _node_path_dirs
    for root in [_builtin_nodes_dir(), *_node_path_dirs()]:
        folder = root / package
        if folder.is_dir():
            return folder.resolve()
    return None


def known_packages() -> list[str]:
    from zros.cli.run import list_packages
    return sorted({'zros', 'configs', *list_packages()})


def package_share_directory(package: str) -> Path:
    """The share directory of `package` (module docstring); PackageNotFoundError otherwise."""
    if package == 'configs':
        return configs_directory()
    if package == 'zros':
        return configs_directory().parent
    folder = _node_package_directory(package)
    if folder is None:
        from zros.cli.run import list_packages
        if package in list_packages():
            raise PackageNotFoundError(f"package '{package}' is installed through an entry point and has "
                                       'no share directory')
        raise PackageNotFoundError(f"package '{package}' not found (known: {', '.join(known_packages())})")
    return folder


def find_launch_file(package: str, name: str) -> Path:
    """`zros launch PKG FILE`: FILE in PKG's share directory or its `launch/` subdirectory;
    for `zros` (and `configs`) that directory is `configs/`."""
    share = configs_directory() if package == 'zros' else package_share_directory(package)
    candidates = [share / name, share / 'launch' / name]
    for candidate in candidates:
        if candidate.is_file():
            return candidate
    tried = ', '.join(str(c) for c in candidates)
    raise LaunchError(f"launch file '{name}' not found in package '{package}' (looked in {tried})")
