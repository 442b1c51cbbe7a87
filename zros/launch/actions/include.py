"""`IncludeLaunchDescription` (`include`): read another launch file here, with arguments."""
from __future__ import annotations

import os
from typing import Any

from zros.launch.action import Action, ActionKwargs, EnterFile, LeaveFile, Parser, launch_tag
from zros.launch.entity import Entity, Scalar
from zros.launch.errors import LaunchFileError
from zros.launch.launch_description_sources import AnyLaunchDescriptionSource, LaunchDescriptionSource
from zros.launch.template import Text

__all__ = ['IncludeLaunchDescription']


class IncludeKwargs(ActionKwargs, total=False):
    launch_description_source: Any
    launch_arguments: list[tuple[Text, Text]]


@launch_tag('include')
class IncludeLaunchDescription(Action):
    """`IncludeLaunchDescription(source, launch_arguments=[(name, value), ...])`;
    YAML `include: {file, arg: [{name, value}]}`.

    `source` is a LaunchDescriptionSource or a path; Python, YAML and XML files include each other.
    As in ROS 2, the include is not a scope: the argument values and any configuration the
    included file sets stay visible after it (wrap the include in a group to contain them).
    A relative path is taken relative to the including file's directory.
    """

    def __init__(self, launch_description_source: Any, *, launch_arguments: Any = None, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        if not isinstance(launch_description_source, LaunchDescriptionSource):
            launch_description_source = AnyLaunchDescriptionSource(
                self._text(launch_description_source, 'launch_description_source'), origin=self.origin)
        self.source = launch_description_source
        pairs = launch_arguments.items() if isinstance(launch_arguments, dict) else (launch_arguments or [])
        self.launch_arguments: list[tuple[Text, Text]] = []
        for pair in pairs:
            try:
                name, value = pair
            except (TypeError, ValueError):
                raise LaunchFileError(self.origin.with_key('launch_arguments'),
                                      f'expected (name, value) pairs, got {pair!r:.60}') from None
            self.launch_arguments.append((self._text(name, 'launch_arguments'),
                                          self._text(value, 'launch_arguments')))

    @property
    def file(self) -> Text:
        return self.source.location

    @classmethod
    def parse(cls, entity: Entity, parser: Parser) -> tuple[type[Action], IncludeKwargs]:
        _, kwargs = super().parse(entity, parser)
        kwargs['launch_description_source'] = parser.text(entity, 'file')
        arguments = []
        for item in entity.get_attr('arg', data_type=list[Entity], optional=True) or []:
            arguments.append((Text.of(item.get_attr('name'), item.origin_of('name')),
                              parser.text(item, 'value', data_type=Scalar)))
            item.assert_complete()
        kwargs['launch_arguments'] = arguments
        return cls, kwargs

    def resolve_path(self, context: Any) -> str:
        path = self.source.location.perform(context)
        if not os.path.isabs(path) and context.current_file:
            path = os.path.join(os.path.dirname(context.current_file), path)
        return os.path.normpath(path)

    def load(self, path: str) -> list[Action]:
        from zros.launch.files import load_launch_file
        return load_launch_file(path, self.source.kind)

    def execute(self, context: Any) -> list[Action]:
        path = self.resolve_path(context)
        if not os.path.isfile(path):
            raise LaunchFileError(self.source.location.origin, f"no such launch file '{path}'")
        values = [(name.perform(context), value.perform(context)) for name, value in self.launch_arguments]
        for name, value in values:
            context.configurations[name] = value
        # Check the cycle before parsing, so a cycle is reported at this include.
        context.enter_file(path, self.source.location.origin)
        context.leave_file()
        actions = self.load(path)
        return [EnterFile(origin=self.source.location.origin, path=path), *actions, LeaveFile(origin=self.origin)]
