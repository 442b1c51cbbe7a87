"""`Shutdown` (`shutdown`) and `EmitEvent(event=Shutdown())`: end the whole launch when this
point is reached."""
from __future__ import annotations

from typing import Any

from zros.launch.action import Action, ActionKwargs, Parser, launch_tag
from zros.launch.entity import Entity, Scalar
from zros.launch.errors import LaunchFileError
from zros.launch.events import Shutdown as ShutdownEvent
from zros.launch.plan import ShutdownEffect
from zros.launch.template import Text

__all__ = ['Shutdown', 'EmitEvent']


class ShutdownKwargs(ActionKwargs, total=False):
    reason: Text | None


class EmitEvent(Action):
    """`EmitEvent(event=...)`. zros's launch knows one event, `launch.events.Shutdown`: every
    process is stopped (SIGINT, then SIGTERM, then SIGKILL)."""

    def __init__(self, *, event: Any, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        if not isinstance(event, ShutdownEvent):
            raise LaunchFileError(self.origin.with_key('event'),
                                  f'zros.launch.events has no {type(event).__name__}; supported: Shutdown')
        self.event = event
        self.reason = self._optional_text(event.reason, 'event')

    def execute(self, context: Any) -> None:
        reason = self.reason.perform(context) if self.reason is not None else ''
        context.emit(ShutdownEffect(reason, self.origin))


@launch_tag('shutdown')
class Shutdown(EmitEvent):
    """`Shutdown(reason=...)`; YAML `shutdown: {reason}`."""

    def __init__(self, *, reason: Any = None, **kwargs: Any) -> None:
        super().__init__(event=ShutdownEvent(reason=reason), **kwargs)

    @classmethod
    def parse(cls, entity: Entity, parser: Parser) -> tuple[type[Action], ShutdownKwargs]:
        _, kwargs = super().parse(entity, parser)
        kwargs['reason'] = parser.text(entity, 'reason', optional=True, data_type=Scalar)
        return cls, kwargs
