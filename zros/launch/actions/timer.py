"""`TimerAction` (`timer`): run actions `period` seconds after the launch reaches it; and
launch_ros's `ROSTimer` (`ros_timer`), the same on ROS time."""
from __future__ import annotations

from typing import Any, Iterable

from zros.launch.action import Action, ActionKwargs, EndCapture, Parser, launch_tag
from zros.launch.actions.scope import scoped
from zros.launch.actions.group import check_actions
from zros.launch.entity import Entity
from zros.launch.errors import LaunchFileError
from zros.launch.plan import TimerEffect
from zros.launch.template import Typed

__all__ = ['TimerAction', 'ROSTimer']


class TimerKwargs(ActionKwargs, total=False):
    period: Typed
    cancel_on_shutdown: Typed | None
    actions: list[Action]


@launch_tag('timer')
class TimerAction(Action):
    """`TimerAction(period=..., actions=[...])`; YAML `timer: {period, children: [...]}`.

    The actions are resolved with everything else before the launch starts (so their errors
    stop the launch before any process runs) and carried out when the timer fires. Their
    configuration changes are scoped to the timer. A timer that has not fired when the launch
    shuts down is cancelled, unless `cancel_on_shutdown` is false: then it fires all the same,
    and its log lines and shutdowns are carried out (a second Shutdown event for the handlers).
    """

    def __init__(self, *, period: Any, actions: Iterable[Action], cancel_on_shutdown: Any = None,
                 **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self._period = self._typed(period, float, 'period')
        self.actions = check_actions(actions, self.origin.with_key('actions'))
        self._cancel_on_shutdown = self._typed(cancel_on_shutdown, bool, 'cancel_on_shutdown')

    @property
    def period(self) -> Any:
        """launch's view: the period [s] as a float, or the substitutions that give it."""
        return self._period.launch_view()

    @property
    def cancel_on_shutdown(self) -> Any:
        return True if self._cancel_on_shutdown is None else self._cancel_on_shutdown.launch_view()

    @classmethod
    def parse(cls, entity: Entity, parser: Parser) -> tuple[type[Action], TimerKwargs]:
        _, kwargs = super().parse(entity, parser)
        kwargs['period'] = parser.typed(entity, 'period', float, optional=False)
        kwargs['cancel_on_shutdown'] = parser.typed(entity, 'cancel_on_shutdown', bool)
        kwargs['actions'] = parser.parse_actions(entity.children)
        return cls, kwargs

    def sub_actions(self) -> list[Action]:
        return self.actions

    def execute(self, context: Any) -> list[Action]:
        period = self._period.perform(context)
        if period < 0:
            raise LaunchFileError(self._period.origin, f'expected a non-negative period, got {period:g}')
        cancel = self._cancel_on_shutdown.perform(context) if self._cancel_on_shutdown is not None else True
        context.begin_capture()
        return [*scoped(self.actions, self.origin),
                EndCapture(origin=self.origin, wrap=lambda effects: self._timer_effect(period, effects, cancel, context))]

    def _timer_effect(self, period: float, effects: list, cancel: bool, context: Any) -> TimerEffect:
        return TimerEffect(period, effects, self.origin, cancel)


@launch_tag('ros_timer')
class ROSTimer(TimerAction):
    """launch_ros's `ROSTimer(period=..., actions=[...])`; YAML `ros_timer: {period, children}`:
    a TimerAction on the launch's ROS time, which is the wall clock unless `SetUseSimTime(True)`
    made it sim time (launch-wide, as it sets launch_ros's own node's `use_sim_time`); then the
    period is counted on /clock (zros.launch.ros_time).
    """

    def _timer_effect(self, period: float, effects: list, cancel: bool, context: Any) -> TimerEffect:
        return TimerEffect(period, effects, self.origin, cancel,
                           sim_time=lambda: bool(getattr(context, 'launch_use_sim_time', False)))
