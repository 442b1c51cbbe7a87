"""launch.actions.declare_launch_argument: DeclareLaunchArgument, for code that imports it from launch's own module
(the class lives in zros.launch.actions.arg with its relatives)."""
from zros.launch.actions.arg import DeclareLaunchArgument

__all__ = ['DeclareLaunchArgument']
