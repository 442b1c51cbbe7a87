"""The executables of the packages in the index: what `zros run` starts and launch checks.

A package's executables are, in lookup order:
1. entry points in the group `zros.nodes` named `PKG/EXECUTABLE` (how an installed package
   registers its own nodes, see README.md, "Running nodes");
2. a ROS package's executables (zros.ament_index_python.ros_packages): the `console_scripts` of
   its setup.py or installed distribution, and the files in an install prefix's `lib/PKG/`;
3. `EXECUTABLE.py` in the folder the package index (zros.ament_index_python.packages) gives as
   the package's scripts: on `ZROS_NODE_PATH`, else shipped with zros (the module
   `nodes.PKG.EXECUTABLE`). Such a file also answers to its file name, `EXECUTABLE.py`: ROS's
   CMake packages install Python scripts under that name (`ros2 run gazebo_ros
   spawn_entity.py`), so launch files say so.

Reading the index walks directories and parses package manifests, so an `Executables` value
reads it once and answers every question about one moment's packages: `zros run`, a launch
file's `<node>` check and `zros pkg executables` each build one. Loading an executable imports
its module; the caller installs zros.import_hook first when the code may be unmodified rclpy.
"""
from __future__ import annotations

import functools
import importlib
import importlib.util
import os
import runpy
import sys
from importlib import metadata
from pathlib import Path
from typing import Any, Callable

from zros.ament_index_python.packages import IndexEntry, PackageNotFoundError, package_index
from zros.ament_index_python.ros_packages import RosPackage
from zros.errors import ZrosError, with_suggestion

__all__ = ['Executables', 'ExecutableNotFoundError', 'executables']


class ExecutableNotFoundError(ZrosError, LookupError):
    """The package has no executable of that name, or it cannot be started (no `main()`)."""


class Executables:
    """One read of the package index and of the `zros.nodes` entry points (module docstring)."""

    def __init__(self) -> None:
        self._index: dict[str, IndexEntry] = package_index()
        self._entry_points = {ep.name: ep for ep in metadata.entry_points(group='zros.nodes')}

    def packages(self) -> list[str]:
        """The packages that may have executables: those whose folder holds scripts, ROS
        packages, and those with `zros.nodes` entry points."""
        found = {name.split('/')[0] for name in self._entry_points}
        found.update(name for name, entry in self._index.items()
                     if entry.scripts is not None or entry.ros_package is not None)
        return sorted(found)

    def of(self, package: str) -> list[str]:
        """The executable names of `package`, sorted (empty for an unknown package)."""
        found = {name.split('/', 1)[1] for name in self._entry_points if name.startswith(package + '/')}
        entry = self._index.get(package)
        if entry is not None and entry.scripts is not None:
            # A launch file beside the scripts (where ROS installs nav2_loopback_sim's) is no script.
            found.update(p.stem for p in entry.scripts.glob('*.py')
                         if not p.stem.startswith('_') and not p.name.endswith('.launch.py'))
        if entry is not None and entry.ros_package is not None:
            found.update(entry.ros_package.executables)
        return sorted(found)

    def name(self, package: str, executable: str) -> str | None:
        """The name `executable` is listed under in `package`, or None: a package folder's
        `spawn_entity.py` is the executable `spawn_entity`, and answers to `spawn_entity.py` too."""
        names = self.of(package)
        if executable in names:
            return executable
        stem = executable[:-3] if executable.endswith('.py') else ''
        scripts = self._index[package].scripts if package in self._index else None
        if stem in names and scripts is not None and (scripts / executable).is_file():
            return stem
        return None

    def load(self, package: str, executable: str) -> Callable[[], Any]:
        """The callable that runs PKG/EXECUTABLE (its `main`, a console script's function, or a
        `lib/<pkg>/` file's runner).

        Raises:
            PackageNotFoundError: no such package (with the closest name, if any).
            ExecutableNotFoundError: no such executable in it, or it has no `main()`.
        """
        entry_point = self._entry_points.get(f'{package}/{executable}')
        if entry_point is not None:
            return entry_point.load()
        packages = self.packages()
        if package not in packages:
            raise PackageNotFoundError(with_suggestion(f"Package '{package}' not found", package, packages))
        names = self.of(package)
        executable = self.name(package, executable) or executable
        if executable not in names:
            raise ExecutableNotFoundError(with_suggestion(
                f"No executable '{executable}' found in package '{package}'", executable, names,
                otherwise=f" (available: {', '.join(names) or 'none'})"))
        entry = self._index[package]
        if entry.ros_package is not None and executable in entry.ros_package.executables:
            return _ros_executable(entry.ros_package, executable)
        if entry.module is not None:
            module = importlib.import_module(f'{entry.module}.{executable}')
        else:
            spec = importlib.util.spec_from_file_location(f'zros_node_{package}_{executable}',
                                                          entry.scripts / f'{executable}.py')
            module = importlib.util.module_from_spec(spec)
            spec.loader.exec_module(module)
        main = getattr(module, 'main', None)
        if not callable(main):
            raise ExecutableNotFoundError(f"'{package}/{executable}' has no main() function")
        return main


def executables(package: str) -> list[str]:
    """The executable names of `package`, sorted; empty when there is no such package."""
    return Executables().of(package)


def _ros_executable(package: RosPackage, executable: str) -> Callable[[], Any]:
    """The callable that runs a ROS package's executable: a console script's `module:function`
    (imported from the package's source folder when it is one), or a `lib/<pkg>/` file."""
    target = package.executables[executable]
    if ':' in target and not Path(target).is_absolute():
        module_name, _, attribute = target.partition(':')
        if package.python_root is not None and str(package.python_root) not in sys.path:
            sys.path.insert(0, str(package.python_root))
        function: Any = importlib.import_module(module_name)
        for part in attribute.split('.'):
            function = getattr(function, part)
        return function
    return functools.partial(_run_script, target)


def _run_script(path: str) -> Any:
    """Run an installed executable file: a Python script in this process (under the import
    hook), anything else (a compiled node) in its place."""
    with open(path, 'rb') as handle:
        first_line = handle.readline()
    if not (first_line.startswith(b'#!') and b'python' in first_line) and not path.endswith('.py'):
        os.execv(path, [path, *sys.argv[1:]])
    try:
        runpy.run_path(path, run_name='__main__')
    except SystemExit as exc:
        return exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 1)
    return 0
