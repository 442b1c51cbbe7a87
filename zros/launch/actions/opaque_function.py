"""launch.actions.opaque_function: OpaqueFunction, for code that imports it from launch's own module
(the class lives in zros.launch.actions.opaque with its relatives)."""
from zros.launch.actions.opaque import OpaqueFunction

__all__ = ['OpaqueFunction']
