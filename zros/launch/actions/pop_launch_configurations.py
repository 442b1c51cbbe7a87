"""launch.actions.pop_launch_configurations: PopLaunchConfigurations, for code that imports it from launch's own module
(the class lives in zros.launch.actions.scope with its relatives)."""
from zros.launch.actions.scope import PopLaunchConfigurations

__all__ = ['PopLaunchConfigurations']
