"""`Shutdown` (`shutdown`) and `EmitEvent(event=Shutdown())`: end the whole launch when this
point is reached; `EmitEvent(event=ChangeState(...))`: ask a lifecycle node for a transition."""
from __future__ import annotations

from typing import Any

from zros.launch.action import Action, ActionKwargs, Parser, launch_tag
from zros.launch.entity import Entity, Scalar
from zros.launch.errors import LaunchFileError
from zros.launch.events import Shutdown as ShutdownEvent
from zros.launch.plan import ChangeStateEffect, ShutdownEffect
from zros.launch.template import Text

__all__ = ['Shutdown', 'EmitEvent']


class ShutdownKwargs(ActionKwargs, total=False):
    reason: Text | None


class EmitEvent(Action):
    """`EmitEvent(event=...)`. zros's launch knows two events: `launch.events.Shutdown` (every
    process is stopped: SIGINT, then SIGTERM, then SIGKILL) and
    `launch_ros.events.lifecycle.ChangeState` (zros.launch.lifecycle).

    In a launch, a Shutdown is a point of the plan (the supervisor stops the launch there and
    then tells the handlers); executed on a context nothing collects effects from, it is
    queued as the event, as launch does."""

    def __init__(self, *, event: Any, **kwargs: Any) -> None:
        from zros.launch.lifecycle import ChangeState
        super().__init__(**kwargs)
        if not isinstance(event, (ShutdownEvent, ChangeState)):
            raise LaunchFileError(self.origin.with_key('event'),
                                  f'zros.launch.events has no {type(event).__name__}; supported: Shutdown, '
                                  'launch_ros.events.lifecycle.ChangeState')
        self.event = event
        self.reason = self._optional_text(event.reason, 'event') if isinstance(event, ShutdownEvent) else None

    def execute(self, context: Any) -> None:
        if not isinstance(self.event, ShutdownEvent):
            event = self.event
            context.emit(ChangeStateEffect(event.lifecycle_node_matcher, event.transition_id,
                                           event.transition.label, self.origin))
            return
        reason = self.reason.perform(context) if self.reason is not None else ''
        if not context.collecting_effects:   # launch's way: the event, for whoever drains the queue
            context.emit_event_sync(ShutdownEvent(reason=reason, due_to_sigint=self.event.due_to_sigint))
            return
        delivered = bool(self.event.due_to_sigint) and not context.noninteractive
        context.emit(ShutdownEffect(reason, self.origin, delivered))


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
