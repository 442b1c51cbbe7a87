"""launch.actions.reset_environment: ResetEnvironment, for code that imports it from launch's own module
(the class lives in zros.launch.actions.scope with its relatives)."""
from zros.launch.actions.scope import ResetEnvironment

__all__ = ['ResetEnvironment']
