"""launch.actions.set_environment_variable: SetEnvironmentVariable, for code that imports it from launch's own module
(the class lives in zros.launch.actions.env with its relatives)."""
from zros.launch.actions.env import SetEnvironmentVariable

__all__ = ['SetEnvironmentVariable']
