"""launch.actions.execute_process: launch's module path of `ExecuteProcess`, which zros keeps in
zros.launch.actions.process (so `from launch.actions.execute_process import ExecuteProcess`
gives the one class)."""
from __future__ import annotations

from zros.launch.actions.process import ExecuteProcess

__all__ = ['ExecuteProcess']
