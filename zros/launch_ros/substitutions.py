"""launch_ros.substitutions: package directories and launch-set parameters."""
from __future__ import annotations

from typing import Any

from zros.launch.files import module_getattr
from zros.launch.substitutions import _CallSubstitution

__all__ = ['FindPackageShare', 'FindPackagePrefix', 'Parameter']

__getattr__ = module_getattr(__name__)


class FindPackageShare(_CallSubstitution):
    """`FindPackageShare('pkg')` (`$(find-pkg-share pkg)`): the package's share directory."""

    _name = 'find-pkg-share'

    def __init__(self, package: Any) -> None:
        super().__init__(package)


class FindPackagePrefix(FindPackageShare):
    """`FindPackagePrefix('pkg')` (`$(find-pkg-prefix pkg)`)."""

    _name = 'find-pkg-prefix'


class Parameter(_CallSubstitution):
    """`Parameter('name', default=...)` (`$(param name)`): a parameter set earlier in the launch
    with SetParameter."""

    _name = 'param'

    def __init__(self, name: Any, *, default: Any = None) -> None:
        super().__init__(name, *(() if default is None else (default,)))
