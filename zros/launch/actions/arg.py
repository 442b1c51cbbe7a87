"""Launch configurations: `DeclareLaunchArgument` (`arg`), `SetLaunchConfiguration` (`let`),
`UnsetLaunchConfiguration`, `ResetLaunchConfigurations` (`reset`)."""
from __future__ import annotations

from typing import Any, Iterable

from zros.launch.action import Action, ActionKwargs, Parser, launch_tag
from zros.launch.context import DeclaredArgument
from zros.launch.entity import Entity, Scalar
from zros.launch.errors import LaunchFileError
from zros.launch.template import Substitution, TemplateSubstitution, Text, describe

__all__ = ['DeclareLaunchArgument', 'SetLaunchConfiguration', 'UnsetLaunchConfiguration', 'ResetLaunchConfigurations']


class ArgKwargs(ActionKwargs, total=False):
    name: str
    default_value: Text | None
    description: str
    choices: tuple[str, ...]


@launch_tag('arg')
class DeclareLaunchArgument(Action):
    """`DeclareLaunchArgument(name, default_value=None, description='', choices=None)`;
    YAML `arg: {name, default, description, choice: [{value}]}`.

    Without a default the argument is required: the command line (`name:=value`) or the
    including file must give it. A value outside `choices` is an error.
    """

    def __init__(self, name: str, *, default_value: Any = None, description: str | None = None,
                 choices: Iterable[str] | None = None, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        if not isinstance(name, str) or not name or '$(' in name:
            raise LaunchFileError(self.origin.with_key('name'),
                                  'an argument name must be plain text, without substitutions')
        self.name = name
        self._conditionally_included = False   # set by LaunchDescription.get_launch_arguments
        self.default = self._optional_text(default_value, 'default_value')
        self.written_description = description or ''
        self.choices = None if choices is None else [str(choice) for choice in choices]
        if self.choices is not None:
            _check_choices(self, default_value, self.choices)

    @property
    def default_value(self) -> list[Substitution] | None:
        """launch's view of the default: a list of substitutions (None: required)."""
        return None if self.default is None else [TemplateSubstitution(self.default.template)]

    @property
    def description(self) -> str:
        """launch's description: the one given (or 'no description given') with the choices."""
        if self.choices is None:
            return self.written_description or 'no description given'
        if not self.written_description:
            return f'One of: {self.choices}'
        return f"{self.written_description.rstrip('.')}. Valid choices are: {self.choices}"

    @classmethod
    def parse(cls, entity: Entity, parser: Parser) -> tuple[type[Action], ArgKwargs]:
        _, kwargs = super().parse(entity, parser)
        kwargs['name'] = entity.get_attr('name')
        kwargs['default_value'] = parser.text(entity, 'default', optional=True, data_type=Scalar)
        kwargs['description'] = entity.get_attr('description', optional=True, data_type=Scalar)
        choices = entity.get_attr('choice', data_type=list[Entity], optional=True)
        if choices is not None:
            values = []
            for choice in choices:
                values.append(choice.get_attr('value', data_type=Scalar))
                choice.assert_complete()
            kwargs['choices'] = tuple(values)
        return cls, kwargs

    def declaration(self, *, conditional: bool = False) -> DeclaredArgument:
        default = describe(self.default.template) if self.default is not None else None
        return DeclaredArgument(self.name, default, self.written_description, tuple(self.choices or ()),
                                self.origin, conditional)

    def execute(self, context: Any) -> None:
        context.declared.setdefault(self.name, self.declaration())
        if self.name not in context.configurations:
            if self.default is None:
                given = ', '.join(f'{k}:={v}' for k, v in context.launch_arguments.items()) or 'none'
                raise self.origin.with_key('name').error(
                    f"Required launch argument '{self.name}' was not given: pass {self.name}:=VALUE "
                    f"(declared arguments: {', '.join(context.declared_names())}; given: {given})")
            context.configurations[self.name] = self.default.perform(context)
        value = context.configurations[self.name]
        if self.choices is not None and value not in self.choices:
            raise self.origin.with_key('choice').error(
                f"launch argument '{self.name}' is '{value}', not one of: {', '.join(self.choices)}")


def _check_choices(action: DeclareLaunchArgument, default_value: Any, choices: list[str]) -> None:
    """At construction, as launch does: choices may not be empty, and a plain-text default
    must be one of them (a substitution is checked when the launch reaches the argument)."""
    if not choices:
        raise LaunchFileError(action.origin.with_key('choices'), 'choices is empty: pass None for no choice list')
    if isinstance(default_value, str) and default_value not in choices:
        raise LaunchFileError(action.origin.with_key('default_value'),
                              f"default value '{default_value}' is not in provided choices: {', '.join(choices)}")


class LetKwargs(ActionKwargs, total=False):
    name: Text
    value: Text


@launch_tag('let')
class SetLaunchConfiguration(Action):
    """`SetLaunchConfiguration(name, value)`; YAML `let: {name, value}`: set a launch
    configuration (read with `LaunchConfiguration(name)` / `$(var name)`)."""

    def __init__(self, name: Any, value: Any, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.name = self._text(name, 'name')
        self.value = self._text(value, 'value')

    @classmethod
    def parse(cls, entity: Entity, parser: Parser) -> tuple[type[Action], LetKwargs]:
        _, kwargs = super().parse(entity, parser)
        kwargs['name'] = parser.text(entity, 'name')
        kwargs['value'] = parser.text(entity, 'value', data_type=Scalar)
        return cls, kwargs

    def execute(self, context: Any) -> None:
        context.configurations[self.name.perform(context)] = self.value.perform(context)


class UnsetLaunchConfiguration(Action):
    """`UnsetLaunchConfiguration(name)`: forget a launch configuration (nothing if it is not
    set); later `LaunchConfiguration(name)` reads fail or take their default."""

    def __init__(self, name: Any, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.name = self._text(name, 'name')

    def execute(self, context: Any) -> None:
        context.configurations.pop(self.name.perform(context), None)


def parse_keep(entity: Entity, parser: Parser) -> list[tuple[Text, Text]] | None:
    """`keep: [{name, value}]` of `group` and `reset`."""
    items = entity.get_attr('keep', data_type=list[Entity], optional=True)
    if items is None:
        return None
    keep = []
    for item in items:
        keep.append((parser.text(item, 'name'), parser.text(item, 'value', data_type=Scalar)))
        item.assert_complete()
    return keep


def configuration_pairs(action: Action, values: Any, key: str) -> list[tuple[Text, Text]]:
    """`launch_configurations={name: value}` (Python) or `keep` pairs (YAML) as Text pairs."""
    if values is None:
        return []
    items = values.items() if isinstance(values, dict) else values
    return [(action._text(name, key), action._text(value, key)) for name, value in items]


@launch_tag('reset')
class ResetLaunchConfigurations(Action):
    """`ResetLaunchConfigurations(launch_configurations=None)`; YAML `reset: {keep: [...]}`:
    clear every launch configuration (and the ROS scope: namespace, set_parameter, set_remap),
    then set the given ones, evaluated before the clearing. Not scoped."""

    def __init__(self, launch_configurations: Any = None, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.launch_configurations = configuration_pairs(self, launch_configurations, 'launch_configurations')

    @classmethod
    def parse(cls, entity: Entity, parser: Parser) -> tuple[type[Action], ActionKwargs]:
        _, kwargs = super().parse(entity, parser)
        kwargs['launch_configurations'] = parse_keep(entity, parser)
        return cls, kwargs

    def execute(self, context: Any) -> None:
        values = {name.perform(context): value.perform(context) for name, value in self.launch_configurations}
        context.reset_configurations(values)
