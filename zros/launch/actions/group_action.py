"""launch.actions.group_action: GroupAction, for code that imports it from launch's own module
(the class lives in zros.launch.actions.group with its relatives)."""
from zros.launch.actions.group import GroupAction

__all__ = ['GroupAction']
