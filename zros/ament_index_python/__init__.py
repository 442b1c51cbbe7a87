"""Where packages are (ament_index_python), for launch files and the `zros pkg` tools.

`from zros.ament_index_python.packages import get_package_share_directory` is the ported form
of ROS 2's import. zros has no colcon install space; zros.ament_index_python.packages says
what a package's share directory is (docs/packages.md).
"""
from __future__ import annotations

from zros.ament_index_python.packages import (PackageNotFoundError, get_package_prefix,
                                              get_package_share_directory, get_package_share_path,
                                              get_packages_with_prefixes)

__all__ = ['PackageNotFoundError', 'get_package_prefix', 'get_package_share_directory',
           'get_package_share_path', 'get_packages_with_prefixes']
