"""`zros run PKG EXECUTABLE [args...]`: find an executable and run it in this process.

Executables are looked up in this order:
1. entry points in the group `zros.nodes` named `PKG/EXECUTABLE` (how an installed
   package registers its own nodes, see README.md, "Running nodes");
2. a ROS package's executables (zros.ament_index_python.ros_packages): the `console_scripts` of
   its setup.py or installed distribution, and the files in an install prefix's `lib/PKG/`;
3. `EXECUTABLE.py` in the folder the package index (zros.ament_index_python.packages) finds for
   PKG: on `ZROS_NODE_PATH`, else shipped with zros (the module `nodes.PKG.EXECUTABLE`). Such a
   file also answers to its file name, `EXECUTABLE.py`: ROS's CMake packages install Python
   scripts under that name (`ros2 run gazebo_ros spawn_entity.py`), so launch files say so.
Every executable is loaded with zros.import_hook installed, so unmodified rclpy code runs as it is.
The module's `main()` is called with sys.argv set to [EXECUTABLE, args...], the way
ros2 run's executables see their arguments (`--ros-args` included).

Session options go before the package: `zros run --connect tcp/10.0.0.1:7447 demo_nodes talker`
(also --listen, --discovery, --domain-id, --zenoh-config). They set the ZROS_* environment
variables before the executable starts (see docs/multi-machine.md); everything after the
executable is passed through untouched.
"""
from __future__ import annotations

import argparse
import functools
import importlib
import importlib.util
import sys
from importlib import metadata
from pathlib import Path
from typing import Any, Callable

__all__ = ['add_arguments', 'main_passthrough', 'find_executable', 'list_executables', 'executable_name']


def add_arguments(parser: argparse.ArgumentParser) -> None:
    from zros.config import add_session_options
    add_session_options(parser)
    parser.add_argument('package_name', help='package, e.g. demo_nodes')
    parser.add_argument('executable_name', help='executable in the package, e.g. talker')
    parser.add_argument('argv', nargs=argparse.REMAINDER, help='arguments for the executable (and --ros-args ...)')


def _builtin_nodes_dir() -> Path:
    import nodes
    return Path(list(nodes.__path__)[0]).resolve()


def list_packages() -> list[str]:
    """The packages that may have executables: those of the package index
    (zros.ament_index_python.packages) with executables in their folder, ROS packages, and those
    with entry points."""
    from zros.ament_index_python.packages import executable_directories, ros_packages
    found = {ep.name.split('/')[0] for ep in metadata.entry_points(group='zros.nodes')}
    return sorted(found.union(executable_directories(), ros_packages()))


def list_executables(package: str) -> list[str]:
    from zros.ament_index_python.packages import executable_directories, ros_packages
    found = {ep.name.split('/', 1)[1] for ep in metadata.entry_points(group='zros.nodes')
             if ep.name.startswith(package + '/')}
    folder = executable_directories().get(package)
    if folder is not None:
        found.update(p.stem for p in folder.glob('*.py') if not p.stem.startswith('_'))
    ros_package = ros_packages().get(package)
    if ros_package is not None:
        found.update(ros_package.executables)
    return sorted(found)


def executable_name(package: str, executable: str, executables: list[str]) -> str | None:
    """The name `executable` is listed under in `executables` (those of `package`), or None.

    A package folder's `spawn_entity.py` is the executable `spawn_entity`, and answers to
    `spawn_entity.py` too: the name CMake-installed Python scripts keep (gazebo_ros's)."""
    if executable in executables:
        return executable
    stem = executable[:-3] if executable.endswith('.py') else ''
    from zros.ament_index_python.packages import executable_directories
    folder = executable_directories().get(package)
    if stem in executables and folder is not None and (folder / executable).is_file():
        return stem
    return None


def _ros_executable(package: Any, executable: str) -> Callable[[], Any]:
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
    import os
    import runpy
    with open(path, 'rb') as handle:
        first_line = handle.readline()
    if not (first_line.startswith(b'#!') and b'python' in first_line) and not path.endswith('.py'):
        os.execv(path, [path, *sys.argv[1:]])
    try:
        runpy.run_path(path, run_name='__main__')
    except SystemExit as exc:
        return exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 1)
    return 0


def find_executable(package: str, executable: str) -> Callable[[], Any]:
    """The callable that runs PKG/EXECUTABLE; CliError (one line) when there is none."""
    from zros.ament_index_python.packages import executable_directories
    from zros.errors import CliError, with_suggestion
    from zros.import_hook import install
    install()  # any package's nodes may be unmodified rclpy code (`import rclpy`, `from std_msgs.msg ...`)
    for ep in metadata.entry_points(group='zros.nodes'):
        if ep.name == f'{package}/{executable}':
            return ep.load()
    packages = list_packages()
    if package not in packages:
        raise CliError(with_suggestion(f"Package '{package}' not found", package, packages))
    executables = list_executables(package)
    executable = executable_name(package, executable, executables) or executable
    if executable not in executables:
        raise CliError(with_suggestion(f"No executable '{executable}' found in package '{package}'", executable,
                                       executables, otherwise=f" (available: {', '.join(executables) or 'none'})"))
    from zros.ament_index_python.packages import ros_packages
    ros_package = ros_packages().get(package)
    if ros_package is not None and executable in ros_package.executables:
        return _ros_executable(ros_package, executable)
    folder = executable_directories()[package]
    if folder.parent == _builtin_nodes_dir():
        module = importlib.import_module(f'nodes.{package}.{executable}')
    else:
        spec = importlib.util.spec_from_file_location(f'zros_node_{package}_{executable}', folder / f'{executable}.py')
        module = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(module)
    main = getattr(module, 'main', None)
    if not callable(main):
        raise CliError(f"'{package}/{executable}' has no main() function")
    return main


def main_passthrough(argv: list[str]) -> int:
    from zros.config import apply_session_options, split_session_options
    from zros.errors import CliError, ZrosError
    options, argv = split_session_options(argv)
    if not argv or argv[0] in ('-h', '--help'):
        print(__doc__.strip())
        print('\nusage: zros run [--connect EP] [--listen EP] [--discovery MODE] [--domain-id N] '
              '[--zenoh-config FILE] PACKAGE EXECUTABLE [args...] [--ros-args ...]')
        print('packages: ' + ', '.join(list_packages()))
        return 0
    if len(argv) == 1:
        raise CliError(f"usage: zros run PACKAGE EXECUTABLE [args...]; executables of '{argv[0]}': "
                       + (', '.join(list_executables(argv[0])) or 'none'))
    package, executable, rest = argv[0], argv[1], argv[2:]
    # The node's signal handling from the start, as zros.init() installs it (zros.signals).
    from zros.signals import install_signal_handlers, signal_received
    install_signal_handlers()
    entry = find_executable(package, executable)
    if options:
        apply_session_options(options)
    sys.argv = [executable, *rest]
    try:
        result = entry()
    except KeyboardInterrupt:
        return 130
    except ZrosError:
        raise   # its one line says what happened (e.g. stopped while waiting for the router)
    except Exception:
        if not signal_received():
            raise
        # SIGTERM shut zros down while the node was still being built (before its main's
        # try/except around spin): what failed under it is the stop that was asked for.
        return 0
    return result if isinstance(result, int) else 0
