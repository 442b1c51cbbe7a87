"""`set_env`, `unset_env`, `append_env`: the environment of the processes started later
(in the same scope), and of `$(env)`."""
from __future__ import annotations

import os
from typing import Any

from zros.launch.actions import Action, ActionKwargs, Parser, launch_tag
from zros.launch.entity import Entity, Scalar
from zros.launch.substitutions import Text, Typed

__all__ = ['SetEnvironment', 'UnsetEnvironment', 'AppendEnvironment']


class EnvKwargs(ActionKwargs, total=False):
    name: Text
    value: Text
    prepend: Typed | None
    separator: Text | None


@launch_tag('set_env')
class SetEnvironment(Action):
    """`set_env: {name, value}`."""

    def __init__(self, *, name: Text, value: Text, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.name, self.value = name, value

    @classmethod
    def parse(cls, entity: Entity, parser: Parser) -> tuple[type[Action], EnvKwargs]:
        _, kwargs = super().parse(entity, parser)
        kwargs['name'] = parser.text(entity, 'name')
        kwargs['value'] = parser.text(entity, 'value', data_type=Scalar)
        return cls, kwargs

    def execute(self, context: Any) -> None:
        context.environment[self.name.perform(context)] = self.value.perform(context)


@launch_tag('unset_env')
class UnsetEnvironment(Action):
    """`unset_env: {name}`."""

    def __init__(self, *, name: Text, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.name = name

    @classmethod
    def parse(cls, entity: Entity, parser: Parser) -> tuple[type[Action], EnvKwargs]:
        _, kwargs = super().parse(entity, parser)
        kwargs['name'] = parser.text(entity, 'name')
        return cls, kwargs

    def execute(self, context: Any) -> None:
        context.environment.pop(self.name.perform(context), None)


@launch_tag('append_env')
class AppendEnvironment(Action):
    """`append_env: {name, value, prepend: false, separator: os.pathsep}`."""

    def __init__(self, *, name: Text, value: Text, prepend: Typed | None = None,
                 separator: Text | None = None, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.name, self.value, self.prepend, self.separator = name, value, prepend, separator

    @classmethod
    def parse(cls, entity: Entity, parser: Parser) -> tuple[type[Action], EnvKwargs]:
        _, kwargs = super().parse(entity, parser)
        kwargs['name'] = parser.text(entity, 'name')
        kwargs['value'] = parser.text(entity, 'value', data_type=Scalar)
        kwargs['prepend'] = parser.typed(entity, 'prepend', bool)
        kwargs['separator'] = parser.text(entity, 'separator', optional=True)
        return cls, kwargs

    def execute(self, context: Any) -> None:
        name = self.name.perform(context)
        value = self.value.perform(context)
        separator = self.separator.perform(context) if self.separator is not None else os.pathsep
        current = context.environment.get(name)
        if current:
            prepend = self.prepend.perform(context) if self.prepend is not None else False
            value = f'{value}{separator}{current}' if prepend else f'{current}{separator}{value}'
        context.environment[name] = value
