"""launch.actions.include_launch_description: IncludeLaunchDescription, for code that imports it from launch's own module
(the class lives in zros.launch.actions.include with its relatives)."""
from zros.launch.actions.include import IncludeLaunchDescription

__all__ = ['IncludeLaunchDescription']
