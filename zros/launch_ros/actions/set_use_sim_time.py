"""launch_ros.actions.set_use_sim_time: launch_ros's module path of `SetUseSimTime`, which zros keeps in
zros.launch.actions.ros (so importing it from here gives the one class)."""
from __future__ import annotations

from zros.launch.actions.ros import SetUseSimTime

__all__ = ['SetUseSimTime']
