"""launch.actions.set_launch_configuration: SetLaunchConfiguration, for code that imports it from launch's own module
(the class lives in zros.launch.actions.arg with its relatives)."""
from zros.launch.actions.arg import SetLaunchConfiguration

__all__ = ['SetLaunchConfiguration']
