"""launch.actions.timer_action: TimerAction, for code that imports it from launch's own module
(the class lives in zros.launch.actions.timer with its relatives)."""
from zros.launch.actions.timer import TimerAction

__all__ = ['TimerAction']
