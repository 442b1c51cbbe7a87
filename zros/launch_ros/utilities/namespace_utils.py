"""launch_ros.utilities.namespace_utils: launch_ros's module path of the namespace helpers,
which zros keeps in zros.launch.namespace_utils (the launch builds LoadNode requests with them)."""
from __future__ import annotations

from zros.launch.namespace_utils import (is_namespace_absolute, is_root_namespace, make_namespace_absolute,
                                         prefix_namespace)

__all__ = ['is_root_namespace', 'is_namespace_absolute', 'prefix_namespace', 'make_namespace_absolute']
