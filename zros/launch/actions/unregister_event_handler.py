"""launch.actions.unregister_event_handler: UnregisterEventHandler, for code that imports it from
launch's own module (the class lives in zros.launch.actions.events with RegisterEventHandler)."""
from zros.launch.actions.events import UnregisterEventHandler

__all__ = ['UnregisterEventHandler']
