"""launch_ros.actions.push_ros_namespace: launch_ros's module path of `PushRosNamespace`, which zros keeps in
zros.launch.actions.group (so importing it from here gives the one class)."""
from __future__ import annotations

from zros.launch.actions.group import PushRosNamespace

__all__ = ['PushRosNamespace', 'PushROSNamespace']

#: launch_ros's newer spelling.
PushROSNamespace = PushRosNamespace
