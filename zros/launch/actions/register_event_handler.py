"""launch.actions.register_event_handler: RegisterEventHandler, for code that imports it from launch's own module
(the class lives in zros.launch.actions.events with its relatives)."""
from zros.launch.actions.events import RegisterEventHandler

__all__ = ['RegisterEventHandler']
