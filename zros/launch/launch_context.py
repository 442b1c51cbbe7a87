"""launch.launch_context: `LaunchContext`, for code that imports it from launch's own module
(the class lives in zros.launch.context with the resolution state it carries)."""
from zros.launch.context import LaunchContext

__all__ = ['LaunchContext']
