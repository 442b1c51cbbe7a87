"""launch_ros.actions.set_parameter: launch_ros's module path of `SetParameter`, which zros keeps in
zros.launch.actions.ros (so importing it from here gives the one class)."""
from __future__ import annotations

from zros.launch.actions.ros import SetParameter

__all__ = ['SetParameter']
