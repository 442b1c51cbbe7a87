"""launch.actions.push_launch_configurations: PushLaunchConfigurations, for code that imports it from launch's own module
(the class lives in zros.launch.actions.scope with its relatives)."""
from zros.launch.actions.scope import PushLaunchConfigurations

__all__ = ['PushLaunchConfigurations']
