"""`IncludeLaunchDescription` (`include`): read another launch file here, with arguments."""
from __future__ import annotations

import os
from typing import Any

from zros.launch.action import Action, ActionKwargs, EnterFile, LeaveFile, Parser, launch_tag
from zros.launch.actions.arg import SetLaunchConfiguration
from zros.launch.context import LaunchContext
from zros.launch.entity import Entity, Scalar
from zros.launch.errors import LaunchError, LaunchFileError, Origin
from zros.launch.launch_description_entity import LaunchDescriptionEntity
from zros.launch.launch_description_sources import (AnyLaunchDescriptionSource, LaunchDescriptionSource,
                                                    LaunchFileSource)
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
    def launch_description_source(self) -> LaunchDescriptionSource:
        return self.source

    @property
    def file(self) -> Text:
        return self.source.location_text

    def describe_sub_entities(self) -> list:
        """The included description when it can be had without running the launch (launch's
        view, which `LaunchDescription.get_launch_arguments` walks)."""
        description = self.source.try_get_launch_description_without_context()
        return [] if description is None else [description]

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
        """The file's path: the location evaluated, a relative one taken from the including
        file's directory (not normalized: it is the source's `location`, as launch keeps it)."""
        path = self.source.location_text.perform(context)
        if not os.path.isabs(path) and context.current_file:
            path = os.path.join(os.path.dirname(context.current_file), path)
        return path

    def load(self, path: str) -> list[Action]:
        from zros.launch.files import load_launch_file
        return load_launch_file(path, self.source.kind)

    def execute(self, context: Any) -> list:
        """The launch arguments as SetLaunchConfiguration actions, then the description (a
        file's between markers that make it the current file), as launch returns them."""
        if isinstance(self.source, LaunchFileSource):
            path = self.resolve_path(context)
            origin = self.source.location_text.origin
            if not os.path.isfile(path):
                raise LaunchFileError(origin, f"no such launch file '{path}'")
            # Check the cycle before parsing, so a cycle is reported at this include.
            context.enter_file(path, origin)
            context.leave_file()
            description = self.source.get_launch_description(context, path)
            included: Any = IncludedFile(description, path, origin)
        else:
            description = included = self.source.get_launch_description(context)
            location = self.source.location
            context.extend_locals({'current_launch_file_path': location,
                                   'current_launch_file_directory': os.path.dirname(location)
                                   if os.path.exists(location) else location})
        self._check_required_arguments(description, context)
        return [*(SetLaunchConfiguration(name, value, origin=self.origin) for name, value in self.launch_arguments),
                included]

    def argument_names(self, context: Any) -> list[str] | None:
        """The names of the launch arguments this include passes (None: one cannot be evaluated
        in `context`)."""
        try:
            return [name.perform(context) for name, _ in self.launch_arguments]
        except LaunchError:
            return None

    def _check_required_arguments(self, description: Any, context: Any) -> None:
        """launch's check: an argument the included description declares without a default,
        and not under a condition, must be passed by this include (or by an include between,
        for one declared deeper); a value set elsewhere does not count."""
        given = self.argument_names(context) or []
        for argument, includes in description.get_launch_arguments_with_include_launch_description_actions():
            if argument._conditionally_included or argument.default is not None:
                continue
            names = given + [name for include in includes or [] for name in include.argument_names(LaunchContext()) or []]
            if argument.name not in names:
                raise LaunchFileError(self.origin, f"Included launch description missing required argument "
                                                   f"'{argument.name}' (description: '{argument.description}'), "
                                                   f"given: [{', '.join(names)}]")


class IncludedFile(LaunchDescriptionEntity):
    """An included file's description as the include returns it: visiting it makes the file the
    current one (`$(dirname)`, relative includes, cycles) around the description's actions."""

    def __init__(self, description: Any, path: str, origin: Origin) -> None:
        self.description, self.path, self.origin = description, path, origin

    def describe(self) -> str:
        return f'<included {self.path}>'

    def describe_sub_entities(self) -> list:
        return [self.description]

    def visit(self, context: Any) -> list:
        return [EnterFile(origin=self.origin, path=self.path), *self.description.entities, LeaveFile(origin=self.origin)]
