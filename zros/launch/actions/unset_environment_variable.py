"""launch.actions.unset_environment_variable: UnsetEnvironmentVariable, for code that imports it from launch's own module
(the class lives in zros.launch.actions.env with its relatives)."""
from zros.launch.actions.env import UnsetEnvironmentVariable

__all__ = ['UnsetEnvironmentVariable']
