"""launch.actions.append_environment_variable: AppendEnvironmentVariable, for code that imports it from launch's own module
(the class lives in zros.launch.actions.env with its relatives)."""
from zros.launch.actions.env import AppendEnvironmentVariable

__all__ = ['AppendEnvironmentVariable']
