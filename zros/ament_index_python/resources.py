"""The ament resource index's functions (ament_index_python.resources), over zros's package index.

The resource type every launch file asks about is `packages` (`has_resource('packages',
'image_view')`: is that package installed?), answered from zros.ament_index_python.packages.
Other resource types are read from the ament index of each install prefix
(`<prefix>/share/ament_index/resource_index/<type>/<name>`), as ament_index_python reads them.
"""
from __future__ import annotations

from pathlib import Path

from zros.ament_index_python.packages import PackageNotFoundError, get_packages_with_prefixes
from zros.ament_index_python.ros_packages import RESOURCE_INDEX as _INDEX, install_prefixes

__all__ = ['has_resource', 'get_resource', 'get_resources', 'get_resource_types', 'get_search_paths']

def get_search_paths() -> list[str]:
    """The install prefixes searched (AMENT_PREFIX_PATH, then this Python environment)."""
    return [str(prefix) for prefix in install_prefixes()]


def get_resource_types() -> set[str]:
    """Every resource type of the prefixes' indexes, and `packages`."""
    types = {'packages'}
    for prefix in install_prefixes():
        if (prefix / _INDEX).is_dir():
            types.update(p.name for p in (prefix / _INDEX).iterdir() if p.is_dir())
    return types


def get_resources(resource_type: str) -> dict[str, str]:
    """{resource name: prefix} of one type (for `packages`: every package zros knows)."""
    if resource_type == 'packages':
        return get_packages_with_prefixes()
    found: dict[str, str] = {}
    for prefix in install_prefixes():
        folder = prefix / _INDEX / resource_type
        if folder.is_dir():
            for marker in sorted(folder.iterdir()):
                found.setdefault(marker.name, str(prefix))
    return found


def has_resource(resource_type: str, resource_name: str) -> str | None:
    """The prefix that holds the resource, or None (truthy when it exists, as ament's)."""
    return get_resources(resource_type).get(resource_name)


def get_resource(resource_type: str, resource_name: str) -> tuple[str, str]:
    """(content of the resource's marker file, its prefix); PackageNotFoundError (a KeyError,
    as ament_index_python's LookupError) when there is none."""
    prefix = has_resource(resource_type, resource_name)
    if prefix is None:
        raise PackageNotFoundError(f"resource '{resource_name}' of type '{resource_type}' not found")
    marker = Path(prefix) / _INDEX / resource_type / resource_name
    return (marker.read_text(encoding='utf-8') if marker.is_file() else ''), prefix
