"""launch_ros.actions.ros_timer: launch_ros's module path of `ROSTimer`, which zros keeps
beside TimerAction in zros.launch.actions.timer (so importing it from here gives the one class)."""
from __future__ import annotations

from zros.launch.actions.timer import ROSTimer

__all__ = ['ROSTimer']
