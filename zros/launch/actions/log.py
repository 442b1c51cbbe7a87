"""`log`: print a message when the launch reaches this point."""
from __future__ import annotations

from typing import Any

from zros.launch.actions import Action, ActionKwargs, Parser, launch_tag
from zros.launch.entity import Entity, Scalar
from zros.launch.plan import LogMessage
from zros.launch.substitutions import Text

__all__ = ['Log', 'LOG_LEVELS']

LOG_LEVELS = ('DEBUG', 'INFO', 'WARNING', 'ERROR')


class LogKwargs(ActionKwargs, total=False):
    message: Text
    level: str


@launch_tag('log')
class Log(Action):
    """`log: {message, level: info}` (level: debug, info, warning or error)."""

    def __init__(self, *, message: Text, level: str = 'INFO', **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.message, self.level = message, level

    @classmethod
    def parse(cls, entity: Entity, parser: Parser) -> tuple[type[Action], LogKwargs]:
        _, kwargs = super().parse(entity, parser)
        kwargs['message'] = parser.text(entity, 'message', data_type=Scalar)
        level = (entity.get_attr('level', optional=True) or 'info').upper()
        level = 'WARNING' if level == 'WARN' else level
        if level not in LOG_LEVELS:
            raise entity.error('level', f"expected one of debug, info, warning, error, got '{level.lower()}'")
        kwargs['level'] = level
        return cls, kwargs

    def execute(self, context: Any) -> None:
        context.emit(LogMessage(self.level, self.message.perform(context), self.origin))
