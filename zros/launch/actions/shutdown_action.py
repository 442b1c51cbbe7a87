"""launch.actions.shutdown_action: Shutdown, for code that imports it from launch's own module
(the class lives in zros.launch.actions.shutdown with its relatives)."""
from zros.launch.actions.shutdown import Shutdown

__all__ = ['Shutdown']
