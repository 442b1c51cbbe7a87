"""Importable interface packages: `from interfaces.std_msgs.msg import String`.

There is no generated code: `interfaces.<pkg>.msg` (and `.srv`, `.action`) are modules made
on first import, whose attributes are classes built from the IDL files on the search path
(`ZROS_INTERFACE_PATH` first, then the `.msg/.srv/.action` files shipped beside this file).
"""
from __future__ import annotations

import importlib.abc
import importlib.machinery
import sys
import types
from typing import Any

_KINDS = ('msg', 'srv', 'action')

#: New name -> the package shipped here (both names give the very same classes, see
#: zros.typesupport). ROS 2 moved turtlesim's interfaces to `turtlesim_msgs` after Jazzy;
#: tutorials use both names, and the turtlesim node must answer either.
PACKAGE_ALIASES = {'turtlesim_msgs': 'turtlesim'}


class _InterfaceModule(types.ModuleType):
    """`interfaces.<pkg>.<kind>`: classes appear as attributes when first asked for."""

    def __getattr__(self, name: str) -> Any:
        if name.startswith('__'):
            raise AttributeError(name)
        from zros import typesupport
        from zros.errors import InterfaceError
        _, package, kind = self.__name__.split('.')
        if typesupport.interface_file(package, kind, name) is None:
            raise AttributeError(f"module '{self.__name__}' has no interface '{name}'")
        try:
            cls = typesupport.get_type(f'{package}/{kind}/{name}')
        except InterfaceError as exc:
            raise ImportError(str(exc)) from None
        setattr(self, name, cls)
        return cls

    def __dir__(self) -> list[str]:
        from zros import typesupport
        _, package, kind = self.__name__.split('.')
        return [n.split('/')[-1] for n in typesupport.list_interfaces(package, (kind,))]

    @property
    def __all__(self) -> list[str]:  # lets `from interfaces.std_msgs.msg import *` work
        return self.__dir__()


class _Finder(importlib.abc.MetaPathFinder, importlib.abc.Loader):
    def find_spec(self, fullname: str, path: Any = None, target: Any = None) -> Any:
        parts = fullname.split('.')
        if parts[0] != __name__ or len(parts) not in (2, 3):
            return None
        from zros import typesupport
        if len(parts) == 2:
            if parts[1] not in typesupport.list_packages():
                return None
            return importlib.machinery.ModuleSpec(fullname, self, is_package=True)
        if parts[2] not in _KINDS or not typesupport.list_interfaces(parts[1], (parts[2],)):
            return None
        return importlib.machinery.ModuleSpec(fullname, self, is_package=False)

    def create_module(self, spec: importlib.machinery.ModuleSpec) -> types.ModuleType:
        if spec.name.count('.') == 2:
            return _InterfaceModule(spec.name)
        from zros import typesupport
        package = PACKAGE_ALIASES.get(spec.name.split('.')[1], spec.name.split('.')[1])
        module = types.ModuleType(spec.name)
        # the package's folders on the search path: a Python module shipped beside the
        # interface files (test_msgs's message_fixtures) imports as `<pkg>.<module>`
        module.__path__ = [str(root / package) for root in typesupport.search_roots() if (root / package).is_dir()]
        return module

    def exec_module(self, module: types.ModuleType) -> None:
        """Nothing to run: the modules are filled lazily."""


if not any(isinstance(f, _Finder) for f in sys.meta_path):
    sys.meta_path.insert(0, _Finder())
