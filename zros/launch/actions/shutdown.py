"""`shutdown`: end the whole launch when this point is reached."""
from __future__ import annotations

from typing import Any

from zros.launch.actions import Action, ActionKwargs, Parser, launch_tag
from zros.launch.entity import Entity, Scalar
from zros.launch.plan import ShutdownEffect
from zros.launch.substitutions import Text

__all__ = ['Shutdown']


class ShutdownKwargs(ActionKwargs, total=False):
    reason: Text | None


@launch_tag('shutdown')
class Shutdown(Action):
    """`shutdown: {reason}`: stops every process (SIGINT, then SIGTERM, then SIGKILL)."""

    def __init__(self, *, reason: Text | None = None, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.reason = reason

    @classmethod
    def parse(cls, entity: Entity, parser: Parser) -> tuple[type[Action], ShutdownKwargs]:
        _, kwargs = super().parse(entity, parser)
        kwargs['reason'] = parser.text(entity, 'reason', optional=True, data_type=Scalar)
        return cls, kwargs

    def execute(self, context: Any) -> None:
        reason = self.reason.perform(context) if self.reason is not None else ''
        context.emit(ShutdownEffect(reason, self.origin))
