"""rpyutils: ROS's helpers for loading C extensions. zros has no C extension; these keep code
that calls them (rclpy's own test package does) working: the directory context does nothing
off Windows, as upstream's, and `import_c_library` imports the named module."""
from __future__ import annotations

import contextlib
import importlib
import os
from typing import Any, Iterator

__all__ = ['add_dll_directories_from_env', 'import_c_library']


@contextlib.contextmanager
def add_dll_directories_from_env(env_name: str) -> Iterator[list]:
    """On Windows, rpyutils adds the directories of `env_name` to the DLL search path while the
    context is open; elsewhere (and here) it adds nothing."""
    added: list = []
    if os.name == 'nt' and hasattr(os, 'add_dll_directory'):
        for folder in filter(os.path.isdir, os.environ.get(env_name, '').split(os.pathsep)):
            added.append(os.add_dll_directory(folder))
    try:
        yield added
    finally:
        for handle in added:
            handle.close()


def import_c_library(name: str, package: str | None = None) -> Any:
    """Import `name` (relative to `package`)."""
    return importlib.import_module(name, package=package)
