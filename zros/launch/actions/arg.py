"""`arg` (declare a launch argument) and `let` (set a launch configuration)."""
from __future__ import annotations

from typing import Any

from zros.launch.actions import Action, ActionKwargs, Parser, launch_tag
from zros.launch.context import DeclaredArgument
from zros.launch.entity import Entity, Scalar
from zros.launch.substitutions import Text, describe

__all__ = ['DeclareArgument', 'SetConfiguration']


class ArgKwargs(ActionKwargs, total=False):
    name: str
    default: Text | None
    description: str
    choices: tuple[str, ...]


@launch_tag('arg')
class DeclareArgument(Action):
    """`arg: {name, default, description, choice: [{value}]}`.

    Without a default the argument is required: the command line (`name:=value`) or the
    including file must give it. A value outside `choice` is an error.
    """

    def __init__(self, *, name: str, default: Text | None = None, description: str = '',
                 choices: tuple[str, ...] = (), **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.name = name
        self.default = default
        self.description = description
        self.choices = choices

    @classmethod
    def parse(cls, entity: Entity, parser: Parser) -> tuple[type[Action], ArgKwargs]:
        _, kwargs = super().parse(entity, parser)
        name = entity.get_attr('name')
        if not name or '$(' in name:
            raise entity.error('name', 'an argument name must be plain text, without substitutions')
        kwargs['name'] = name
        kwargs['default'] = parser.text(entity, 'default', optional=True, data_type=Scalar)
        kwargs['description'] = entity.get_attr('description', optional=True, data_type=Scalar) or ''
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
        return DeclaredArgument(self.name, default, self.description, self.choices, self.origin, conditional)

    def execute(self, context: Any) -> None:
        context.declared.setdefault(self.name, self.declaration())
        if self.name not in context.configurations:
            if self.default is None:
                given = ', '.join(f'{k}:={v}' for k, v in context.launch_arguments.items()) or 'none'
                raise self.origin.with_key('name').error(
                    f"required launch argument '{self.name}' was not given: pass {self.name}:=VALUE "
                    f"(declared arguments: {', '.join(context.declared_names())}; given: {given})")
            context.configurations[self.name] = self.default.perform(context)
        value = context.configurations[self.name]
        if self.choices and value not in self.choices:
            raise self.origin.with_key('choice').error(
                f"launch argument '{self.name}' is '{value}', not one of: {', '.join(self.choices)}")


class LetKwargs(ActionKwargs, total=False):
    name: str
    value: Text


@launch_tag('let')
class SetConfiguration(Action):
    """`let: {name, value}`: set a launch configuration (read with `$(var name)`)."""

    def __init__(self, *, name: str, value: Text, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.name = name
        self.value = value

    @classmethod
    def parse(cls, entity: Entity, parser: Parser) -> tuple[type[Action], LetKwargs]:
        _, kwargs = super().parse(entity, parser)
        kwargs['name'] = entity.get_attr('name')
        kwargs['value'] = parser.text(entity, 'value', data_type=Scalar)
        return cls, kwargs

    def execute(self, context: Any) -> None:
        context.configurations[self.name] = self.value.perform(context)
