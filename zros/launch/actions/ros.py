"""launch_ros's scope actions: `SetParameter` (`set_parameter`), `SetRemap` (`set_remap`),
`SetUseSimTime` (`set_use_sim_time`): what every later node in the scope gets."""
from __future__ import annotations

from typing import Any

from zros.launch.action import Action, ActionKwargs, Parser, launch_tag
from zros.launch.context import RosScope
from zros.launch.entity import Entity
from zros.launch.parameters import ParamValue
from zros.launch.template import Text, Typed

__all__ = ['SetParameter', 'SetRemap', 'SetUseSimTime']


class SetParameterKwargs(ActionKwargs, total=False):
    name: Text
    value: ParamValue


@launch_tag('set_parameter')
class SetParameter(Action):
    """`SetParameter(name, value)`; YAML `set_parameter: {name, value, type}`: a parameter for
    every later node in the scope (a node's own parameters override it)."""

    def __init__(self, name: Any, value: Any, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.name = self._text(name, 'name')
        self.value = value if isinstance(value, ParamValue) else ParamValue.of(value, self.origin.with_key('value'))

    @classmethod
    def parse(cls, entity: Entity, parser: Parser) -> tuple[type[Action], SetParameterKwargs]:
        _, kwargs = super().parse(entity, parser)
        kwargs['name'] = parser.text(entity, 'name')
        kwargs['value'] = ParamValue.from_entity(entity)
        return cls, kwargs

    def execute(self, context: Any) -> None:
        RosScope.of(context).add_param((self.name.perform(context), self.value.perform(context)))


class SetRemapKwargs(ActionKwargs, total=False):
    src: Text
    dst: Text


@launch_tag('set_remap')
class SetRemap(Action):
    """`SetRemap(src, dst)`; YAML `set_remap: {from, to}`: a remapping for every later node in
    the scope (applied before the node's own remappings, so it wins, as in launch_ros)."""

    def __init__(self, src: Any, dst: Any, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.src, self.dst = self._text(src, 'src'), self._text(dst, 'dst')

    @classmethod
    def parse(cls, entity: Entity, parser: Parser) -> tuple[type[Action], SetRemapKwargs]:
        _, kwargs = super().parse(entity, parser)
        kwargs['src'] = parser.text(entity, 'from')
        kwargs['dst'] = parser.text(entity, 'to')
        return cls, kwargs

    def execute(self, context: Any) -> None:
        RosScope.of(context).add_remap(self.src.perform(context), self.dst.perform(context))


class SetUseSimTimeKwargs(ActionKwargs, total=False):
    value: Typed


@launch_tag('set_use_sim_time')
class SetUseSimTime(Action):
    """`SetUseSimTime(True)`; YAML `set_use_sim_time: {value: true}`: `use_sim_time` for every
    later node in the scope."""

    def __init__(self, value: Any, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.value = self._typed(value, bool, 'value')

    @classmethod
    def parse(cls, entity: Entity, parser: Parser) -> tuple[type[Action], SetUseSimTimeKwargs]:
        _, kwargs = super().parse(entity, parser)
        kwargs['value'] = parser.typed(entity, 'value', bool, optional=False)
        return cls, kwargs

    def execute(self, context: Any) -> None:
        RosScope.of(context).add_param(('use_sim_time', self.value.perform(context)))
