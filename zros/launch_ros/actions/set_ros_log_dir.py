"""launch_ros.actions.set_ros_log_dir: launch_ros's module path of `SetROSLogDir`, which zros
keeps with the other scope actions in zros.launch.actions.ros (so importing it from here gives
the one class)."""
from __future__ import annotations

from zros.launch.actions.ros import SetROSLogDir

__all__ = ['SetROSLogDir']
