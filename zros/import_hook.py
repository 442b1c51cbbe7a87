"""Run unmodified ROS 2 Python programs on zros: an import hook that answers ROS's module
names with zros's, so `import rclpy` and `from std_msgs.msg import String` just work.

    zros python my_node.py [args...]            # the hook installed, then the program run
    import zros.import_hook; zros.import_hook.install()   # or opt in from Python

`module_target` is the porting rule (also what `zros port` writes into files):
- `rclpy[.x]` -> `zros[.x]`;
- `<pkg>.msg|srv|action` -> `interfaces.<pkg>.msg|srv|action` (and `<pkg>` -> `interfaces.<pkg>`
  for an interface package that is not installed as Python);
- a ROS Python library `X[.y]` (tf2_ros, launch, launch_ros, nav2_simple_commander, cv_bridge,
  sensor_msgs_py, tf_transformations, ament_index_python, ...) -> `zros.X[.y]`, and any other
  `X` for which `zros.X` exists, unless a real `X` is installed (the stdlib's `logging` stays);
- ROS 1's `sensor_msgs.point_cloud2` -> `zros.sensor_msgs_py.point_cloud2`.

An aliased module is the zros module itself (`rclpy.node.Node is zros.node.Node`).
"""
from __future__ import annotations

import importlib
import importlib.abc
import importlib.machinery
import importlib.util
import sys
from typing import Any, Callable

__all__ = ['module_target', 'install', 'uninstall', 'ROS_LIBRARIES', 'INTERFACE_KINDS']

INTERFACE_KINDS = ('msg', 'srv', 'action')

#: ROS Python libraries whose zros counterpart is `zros.<name>` (the porting rule names them
#: even before zros has one, so the error says which zros module is missing).
ROS_LIBRARIES = frozenset({
    'ament_index_python', 'cv_bridge', 'launch', 'launch_ros', 'launch_testing', 'launch_xml', 'launch_yaml',
    'message_filters', 'nav2_common', 'nav2_simple_commander', 'rosbag2_py', 'sensor_msgs_py', 'tf2_geometry_msgs', 'tf2_ros',
    'tf2_py', 'tf_transformations', 'xacro',
})

_RENAMED = {'sensor_msgs.point_cloud2': 'zros.sensor_msgs_py.point_cloud2'}


def _zros_has(name: str) -> bool:
    try:
        return importlib.util.find_spec(f'zros.{name}') is not None
    except (ImportError, ValueError):
        return False


def _is_interface_package(name: str) -> bool:
    """Whether `name/msg` (or srv, action) is on the interface search path. Looked up on disk
    only: this runs inside other modules' imports (numpy's included), so it must not import
    the message machinery."""
    import os
    from pathlib import Path
    roots = [Path(p) for p in os.environ.get('ZROS_INTERFACE_PATH', '').split(os.pathsep) if p]
    spec = importlib.util.find_spec('interfaces')
    roots += [Path(p) for p in (spec.submodule_search_locations or [])] if spec else []
    from interfaces import PACKAGE_ALIASES
    name = PACKAGE_ALIASES.get(name, name)
    return any((root / name / kind).is_dir() for root in roots for kind in INTERFACE_KINDS)


def module_target(name: str, installed: Callable[[str], bool] = lambda top: False) -> str | None:
    """The zros module that stands for ROS module `name`, or None to leave it alone.

    Args:
        installed: whether a top-level module is really available; such a module is only
            replaced for rclpy and the interface kinds.
    """
    if name in _RENAMED:
        return _RENAMED[name]
    parts = name.split('.')
    top = parts[0]
    if top in ('zros', 'interfaces'):
        return None
    if top == 'rclpy':
        return '.'.join(['zros', *parts[1:]])
    if len(parts) >= 2 and parts[1] in INTERFACE_KINDS and top not in ROS_LIBRARIES:
        return f'interfaces.{name}'  # `launch.action` is launch's module, not an interface kind
    if installed(top):
        return None
    if top in ROS_LIBRARIES or _zros_has(top):
        return f'zros.{name}'
    if len(parts) == 1 and _is_interface_package(top):
        return f'interfaces.{top}'
    return None


class _AliasLoader(importlib.abc.Loader):
    """Loads a ROS name as the zros module itself (imported under its own name first)."""

    def __init__(self, target: str) -> None:
        self._target = target
        self._spec: Any = None

    def create_module(self, spec: importlib.machinery.ModuleSpec) -> Any:
        module = importlib.import_module(self._target)
        self._spec = module.__spec__
        return module

    def exec_module(self, module: Any) -> None:
        module.__spec__ = self._spec  # the import system set the alias's spec; keep the module's own


class RosModuleFinder(importlib.abc.MetaPathFinder):
    """First on sys.meta_path; claims only the names module_target maps."""

    def find_spec(self, fullname: str, path: Any = None, target: Any = None) -> importlib.machinery.ModuleSpec | None:
        try:
            mapped = module_target(fullname, self._installed)
        except Exception:  # noqa: BLE001 - a finder must never break an unrelated import
            return None
        if mapped is None:
            return None
        return importlib.machinery.ModuleSpec(fullname, _AliasLoader(mapped), is_package=True)

    def _installed(self, top: str) -> bool:
        loaded = sys.modules.get(top)
        if loaded is not None:
            # an alias this hook made (`launch` is zros.launch) is no install of the real thing:
            # its submodules must be aliased too, or `launch.conditions` loads a second copy
            spec = getattr(loaded, '__spec__', None)
            return getattr(spec, 'name', top) == top
        for finder in sys.meta_path:
            if finder is self or not hasattr(finder, 'find_spec'):
                continue
            try:
                spec = finder.find_spec(top, None)
            except (ImportError, ValueError):
                continue
            # A bare folder of that name on sys.path (launch's own `test/launch` of test files,
            # no __init__.py) is a namespace package, not the library installed.
            if spec is not None and spec.origin is not None:
                return True
        return False


def install() -> RosModuleFinder:
    """Put the hook first on sys.meta_path (once); returns it."""
    for finder in sys.meta_path:
        if isinstance(finder, RosModuleFinder):
            return finder
    finder = RosModuleFinder()
    sys.meta_path.insert(0, finder)
    return finder


def uninstall() -> None:
    sys.meta_path[:] = [f for f in sys.meta_path if not isinstance(f, RosModuleFinder)]
