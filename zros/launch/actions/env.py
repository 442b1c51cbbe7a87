"""`SetEnvironmentVariable` (`set_env`), `UnsetEnvironmentVariable` (`unset_env`),
`AppendEnvironmentVariable` (`append_env`): the environment of the processes started later
(in the same scope), and of `EnvironmentVariable` / `$(env)`."""
from __future__ import annotations

import os
from typing import Any

from zros.launch.action import Action, ActionKwargs, Parser, launch_tag
from zros.launch.entity import Entity, Scalar
from zros.launch.template import Text, Typed

__all__ = ['SetEnvironmentVariable', 'UnsetEnvironmentVariable', 'AppendEnvironmentVariable']


class EnvKwargs(ActionKwargs, total=False):
    name: Text
    value: Text
    prepend: Typed | None
    separator: Text


@launch_tag('set_env')
class SetEnvironmentVariable(Action):
    """`SetEnvironmentVariable(name, value)`; YAML `set_env: {name, value}`."""

    def __init__(self, name: Any, value: Any, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.name, self.value = self._text(name, 'name'), self._text(value, 'value')

    @classmethod
    def parse(cls, entity: Entity, parser: Parser) -> tuple[type[Action], EnvKwargs]:
        _, kwargs = super().parse(entity, parser)
        kwargs['name'] = parser.text(entity, 'name')
        kwargs['value'] = parser.text(entity, 'value', data_type=Scalar)
        return cls, kwargs

    def execute(self, context: Any) -> None:
        context.environment[self.name.perform(context)] = self.value.perform(context)


@launch_tag('unset_env')
class UnsetEnvironmentVariable(Action):
    """`UnsetEnvironmentVariable(name)`; YAML `unset_env: {name}`."""

    def __init__(self, name: Any, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.name = self._text(name, 'name')

    @classmethod
    def parse(cls, entity: Entity, parser: Parser) -> tuple[type[Action], EnvKwargs]:
        _, kwargs = super().parse(entity, parser)
        kwargs['name'] = parser.text(entity, 'name')
        return cls, kwargs

    def execute(self, context: Any) -> None:
        context.environment.pop(self.name.perform(context), None)


@launch_tag('append_env')
class AppendEnvironmentVariable(Action):
    """`AppendEnvironmentVariable(name, value, prepend=False, separator=os.pathsep)`;
    YAML `append_env: {name, value, prepend, separator}`."""

    def __init__(self, name: Any, value: Any, *, prepend: Any = None, separator: Any = os.pathsep,
                 **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.name, self.value = self._text(name, 'name'), self._text(value, 'value')
        self.prepend = self._typed(prepend, bool, 'prepend')
        self.separator = self._text(separator, 'separator')

    @classmethod
    def parse(cls, entity: Entity, parser: Parser) -> tuple[type[Action], EnvKwargs]:
        _, kwargs = super().parse(entity, parser)
        kwargs['name'] = parser.text(entity, 'name')
        kwargs['value'] = parser.text(entity, 'value', data_type=Scalar)
        kwargs['prepend'] = parser.typed(entity, 'prepend', bool)
        separator = parser.text(entity, 'separator', optional=True)
        if separator is not None:
            kwargs['separator'] = separator
        return cls, kwargs

    def execute(self, context: Any) -> None:
        name = self.name.perform(context)
        value = self.value.perform(context)
        separator = self.separator.perform(context)
        current = context.environment.get(name)
        if current:
            prepend = self.prepend.perform(context) if self.prepend is not None else False
            value = f'{value}{separator}{current}' if prepend else f'{current}{separator}{value}'
        context.environment[name] = value
