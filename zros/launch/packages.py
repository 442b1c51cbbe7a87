"""`zros launch PKG FILE`: a launch file in a package (the package index is
zros.ament_index_python.packages)."""
from __future__ import annotations

from pathlib import Path

from zros.ament_index_python.packages import PackageNotFoundError, get_package_share_path
from zros.errors import with_suggestion
from zros.launch.errors import LaunchError

__all__ = ['configs_directory', 'find_launch_file']


def configs_directory() -> Path:
    """The `configs/` directory shipped with zros."""
    return get_package_share_path('configs')


def find_launch_file(package: str, name: str) -> Path:
    """FILE in PKG's share directory or its `launch/` subdirectory (for `zros`, `configs/`)."""
    try:
        share = configs_directory() if package == 'zros' else get_package_share_path(package)
    except PackageNotFoundError as exc:
        raise LaunchError(str(exc)) from None
    candidates = [share / name, share / 'launch' / name]
    for candidate in candidates:
        if candidate.is_file():
            return candidate
    found = sorted(p.name for p in (share / 'launch').glob('*launch*')) if (share / 'launch').is_dir() else []
    hint = f"; launch files: {', '.join(found)}" if found else ''
    tried = ', '.join(str(c) for c in candidates)
    raise LaunchError(with_suggestion(f"launch file '{name}' not found in package '{package}'", name, found,
                                      otherwise=f' (looked in {tried}{hint})'))
