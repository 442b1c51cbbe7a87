"""launch.actions.execute_process: ExecuteProcess, for code that imports it from launch's own module
(the class lives in zros.launch.actions.process with its relatives)."""
from zros.launch.actions.process import ExecuteProcess

__all__ = ['ExecuteProcess']
