"""`LogInfo` (`log`): print a message when the launch reaches this point."""
from __future__ import annotations

from typing import Any

from zros.launch.action import Action, ActionKwargs, Parser, launch_tag
from zros.launch.entity import Entity, Scalar
from zros.launch.errors import LaunchFileError
from zros.launch.plan import LogMessage
from zros.launch.template import Text

__all__ = ['LogInfo', 'LOG_LEVELS']

LOG_LEVELS = ('DEBUG', 'INFO', 'WARNING', 'ERROR')


class LogKwargs(ActionKwargs, total=False):
    msg: Text
    level: str


@launch_tag('log')
class LogInfo(Action):
    """`LogInfo(msg=..., level='INFO')`; YAML `log: {message, level}` (debug, info, warning,
    error; `level` is zros's addition). Printed as `[INFO] [launch.user]: ...`."""

    def __init__(self, *, msg: Any, level: str = 'INFO', **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.msg = self._text(msg, 'msg')
        level = str(level).upper()
        level = 'WARNING' if level == 'WARN' else level
        if level not in LOG_LEVELS:
            raise LaunchFileError(self.origin.with_key('level'),
                                  f"expected one of debug, info, warning, error, got '{level.lower()}'")
        self.level = level

    @classmethod
    def parse(cls, entity: Entity, parser: Parser) -> tuple[type[Action], LogKwargs]:
        _, kwargs = super().parse(entity, parser)
        kwargs['msg'] = parser.text(entity, 'message', data_type=Scalar)
        kwargs['level'] = entity.get_attr('level', optional=True) or 'info'
        return cls, kwargs

    def execute(self, context: Any) -> None:
        context.emit(LogMessage(self.level, self.msg.perform(context), self.origin))
