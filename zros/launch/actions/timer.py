"""`timer`: run children `period` seconds after the launch reaches it."""
from __future__ import annotations

from typing import Any

from zros.launch.actions import Action, ActionKwargs, Parser, PopScope, PushScope, launch_tag
from zros.launch.entity import Entity
from zros.launch.errors import LaunchFileError
from zros.launch.plan import TimerEffect
from zros.launch.substitutions import Typed

__all__ = ['Timer']


class TimerKwargs(ActionKwargs, total=False):
    period: Typed
    cancel_on_shutdown: Typed | None
    children: list[Action]


@launch_tag('timer')
class Timer(Action):
    """`timer: {period, children: [...]}`.

    The children are resolved with everything else before the launch starts (so their errors
    stop the launch before any process runs) and carried out when the timer fires. Their
    configuration changes are scoped to the timer. A timer that has not fired when the launch
    shuts down is cancelled.
    """

    def __init__(self, *, period: Typed, children: list[Action], cancel_on_shutdown: Typed | None = None,
                 **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.period, self.children, self.cancel_on_shutdown = period, children, cancel_on_shutdown

    @classmethod
    def parse(cls, entity: Entity, parser: Parser) -> tuple[type[Action], TimerKwargs]:
        _, kwargs = super().parse(entity, parser)
        kwargs['period'] = parser.typed(entity, 'period', float, optional=False)
        kwargs['cancel_on_shutdown'] = parser.typed(entity, 'cancel_on_shutdown', bool)
        kwargs['children'] = parser.parse_actions(entity.children)
        return cls, kwargs

    def sub_actions(self) -> list[Action]:
        return self.children

    def execute(self, context: Any) -> list[Action]:
        period = self.period.perform(context)
        if period < 0:
            raise LaunchFileError(self.period.origin, f'expected a non-negative period, got {period:g}')
        context.begin_capture()
        return [PushScope(origin=self.origin), *self.children, PopScope(origin=self.origin),
                _EndTimer(origin=self.origin, period=period)]


class _EndTimer(Action):
    def __init__(self, *, period: float, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.period = period

    def execute(self, context: Any) -> None:
        effects = context.end_capture()
        context.emit(TimerEffect(self.period, effects, self.origin))
