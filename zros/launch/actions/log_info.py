"""launch.actions.log_info: LogInfo, for code that imports it from launch's own module
(the class lives in zros.launch.actions.log with its relatives)."""
from zros.launch.actions.log import LogInfo

__all__ = ['LogInfo']
