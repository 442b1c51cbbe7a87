"""launch.actions.reset_launch_configurations: ResetLaunchConfigurations, for code that imports it from launch's own module
(the class lives in zros.launch.actions.arg with its relatives)."""
from zros.launch.actions.arg import ResetLaunchConfigurations

__all__ = ['ResetLaunchConfigurations']
