"""`include`: read another launch file here, with arguments."""
from __future__ import annotations

import os
from typing import Any

from zros.launch.actions import Action, ActionKwargs, EnterFile, LeaveFile, Parser, launch_tag
from zros.launch.entity import Entity, Scalar, load_launch_entities
from zros.launch.errors import LaunchFileError
from zros.launch.substitutions import Text

__all__ = ['Include', 'parse_launch_file']


def parse_launch_file(path: str) -> list[Action]:
    """Load and parse a launch file into actions (no substitution is evaluated)."""
    return Parser(path).parse_actions(load_launch_entities(path))


class IncludeKwargs(ActionKwargs, total=False):
    file: Text
    arguments: list[tuple[str, Text]]


@launch_tag('include')
class Include(Action):
    """`include: {file, arg: [{name, value}]}`.

    As in ROS 2, the include is not a scope: the `arg` values and any configuration the
    included file sets stay visible after it (wrap the include in a `group` to contain them).
    A relative `file` is taken relative to the including file's directory.
    """

    def __init__(self, *, file: Text, arguments: list[tuple[str, Text]] | None = None, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.file = file
        self.arguments = arguments or []

    @classmethod
    def parse(cls, entity: Entity, parser: Parser) -> tuple[type[Action], IncludeKwargs]:
        _, kwargs = super().parse(entity, parser)
        kwargs['file'] = parser.text(entity, 'file')
        arguments = []
        for item in entity.get_attr('arg', data_type=list[Entity], optional=True) or []:
            arguments.append((item.get_attr('name'), parser.text(item, 'value', data_type=Scalar)))
            item.assert_complete()
        kwargs['arguments'] = arguments
        return cls, kwargs

    def resolve_path(self, context: Any) -> str:
        path = self.file.perform(context)
        if not os.path.isabs(path) and context.current_file:
            path = os.path.join(os.path.dirname(context.current_file), path)
        return os.path.normpath(path)

    def execute(self, context: Any) -> list[Action]:
        path = self.resolve_path(context)
        if not os.path.isfile(path):
            raise LaunchFileError(self.file.origin, f"no such launch file '{path}'")
        values = [(name, value.perform(context)) for name, value in self.arguments]
        for name, value in values:
            context.configurations[name] = value
        # Check the cycle before parsing, so a cycle is reported at this include.
        context.enter_file(path, self.file.origin)
        context.leave_file()
        actions = parse_launch_file(path)
        return [EnterFile(origin=self.file.origin, path=path), *actions, LeaveFile(origin=self.origin)]
