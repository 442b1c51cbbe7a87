"""launch.actions.unset_launch_configuration: UnsetLaunchConfiguration, for code that imports it from launch's own module
(the class lives in zros.launch.actions.arg with its relatives)."""
from zros.launch.actions.arg import UnsetLaunchConfiguration

__all__ = ['UnsetLaunchConfiguration']
