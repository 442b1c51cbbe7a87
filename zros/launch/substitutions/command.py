"""launch.substitutions.command: launch's module path of `Command` (nav2_minimal_tb3_sim's
spawn_tb3.launch.py imports it from here); the class is zros.launch.substitutions's."""
from __future__ import annotations

from zros.launch.substitutions import Command

__all__ = ['Command']
