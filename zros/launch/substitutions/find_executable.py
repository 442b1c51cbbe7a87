"""launch.substitutions.find_executable: launch's module path of `FindExecutable` (imported from
here by nav2_minimal_tb3_sim's spawn_tb3.launch.py); the class is zros.launch.substitutions's."""
from __future__ import annotations

from zros.launch.substitutions import FindExecutable

__all__ = ['FindExecutable']
