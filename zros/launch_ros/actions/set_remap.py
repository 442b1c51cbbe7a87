"""launch_ros.actions.set_remap: launch_ros's module path of `SetRemap`, which zros keeps in
zros.launch.actions.ros (so importing it from here gives the one class)."""
from __future__ import annotations

from zros.launch.actions.ros import SetRemap

__all__ = ['SetRemap']
