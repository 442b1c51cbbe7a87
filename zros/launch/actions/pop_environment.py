"""launch.actions.pop_environment: PopEnvironment, for code that imports it from launch's own module
(the class lives in zros.launch.actions.scope with its relatives)."""
from zros.launch.actions.scope import PopEnvironment

__all__ = ['PopEnvironment']
