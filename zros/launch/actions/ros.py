"""ROS scope tags: `set_parameter`, `set_remap`, `set_use_sim_time`, and the parameter value
rule shared with `node`'s `param` entries."""
from __future__ import annotations

from typing import Any, NamedTuple

from zros.launch.actions import Action, ActionKwargs, Parser, launch_tag
from zros.launch.entity import Entity
from zros.launch.errors import LaunchFileError, Origin
from zros.launch.substitutions import Text, Typed

__all__ = ['ParamValue', 'SetParameter', 'SetRemap', 'SetUseSimTime', 'PARAM_TYPES']

PARAM_TYPES = ('str', 'int', 'float', 'bool')


class ParamValue(NamedTuple):
    """A parameter value as written: a YAML scalar or list kept as is, or a string with
    substitutions that is typed by YAML after evaluation (`'1'` -> 1, as `-p name:=1`), unless
    `type: str` (or int, float, bool) says otherwise."""

    value: Any
    type: str | None
    origin: Origin

    @classmethod
    def from_entity(cls, entity: Entity, parser: Parser, key: str = 'value') -> 'ParamValue':
        raw = entity.get_attr(key, data_type=Any)
        origin = entity.origin_of(key)
        type_name = entity.get_attr('type', optional=True)
        if type_name is not None and type_name not in PARAM_TYPES:
            raise entity.error('type', f"expected one of {', '.join(PARAM_TYPES)}, got '{type_name}'")
        if isinstance(raw, str):
            return cls(Text.parse(raw, origin), type_name, origin)
        if isinstance(raw, list):
            items = []
            for item in raw:
                if isinstance(item, (dict, list)) or item is None:
                    raise LaunchFileError(origin, 'a list parameter holds only strings, numbers or bools')
                items.append(Text.parse(item, origin) if isinstance(item, str) else item)
            return cls(items, type_name, origin)
        if isinstance(raw, dict):
            raise LaunchFileError(origin, "a parameter value cannot be a mapping: use nested 'param:' entries")
        if raw is None:
            raise LaunchFileError(origin, 'a parameter needs a value')
        return cls(raw, type_name, origin)

    def perform(self, context: Any) -> Any:
        from zros.parameter import parse_parameter_value
        if isinstance(self.value, Text):
            text = self.value.perform(context)
            if self.type is None:
                return parse_parameter_value(text)
            return self._coerce(text)
        if isinstance(self.value, list):
            return [item.perform(context) if isinstance(item, Text) else item for item in self.value]
        return self._coerce(self.value) if self.type is not None else self.value

    def _coerce(self, value: Any) -> Any:
        if self.type == 'str':
            if isinstance(value, bool):
                return 'true' if value else 'false'
            return str(value)
        data_type = {'int': int, 'float': float, 'bool': bool}[self.type]
        return Typed(data_type, None, self.origin).convert(value)


class SetParameterKwargs(ActionKwargs, total=False):
    name: Text
    value: ParamValue


@launch_tag('set_parameter')
class SetParameter(Action):
    """`set_parameter: {name, value}`: a parameter for every later node in the scope (a node's
    own `param` entries override it)."""

    def __init__(self, *, name: Text, value: ParamValue, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.name, self.value = name, value

    @classmethod
    def parse(cls, entity: Entity, parser: Parser) -> tuple[type[Action], SetParameterKwargs]:
        _, kwargs = super().parse(entity, parser)
        kwargs['name'] = parser.text(entity, 'name')
        kwargs['value'] = ParamValue.from_entity(entity, parser)
        return cls, kwargs

    def execute(self, context: Any) -> None:
        context.ros.params.append((self.name.perform(context), self.value.perform(context)))


class SetRemapKwargs(ActionKwargs, total=False):
    source: Text
    target: Text


@launch_tag('set_remap')
class SetRemap(Action):
    """`set_remap: {from, to}`: a remapping for every later node in the scope (applied before
    the node's own `remap` entries, so it wins, as in launch_ros)."""

    def __init__(self, *, source: Text, target: Text, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.source, self.target = source, target

    @classmethod
    def parse(cls, entity: Entity, parser: Parser) -> tuple[type[Action], SetRemapKwargs]:
        _, kwargs = super().parse(entity, parser)
        kwargs['source'] = parser.text(entity, 'from')
        kwargs['target'] = parser.text(entity, 'to')
        return cls, kwargs

    def execute(self, context: Any) -> None:
        context.ros.remaps.append((self.source.perform(context), self.target.perform(context)))


class SetUseSimTimeKwargs(ActionKwargs, total=False):
    value: Typed


@launch_tag('set_use_sim_time')
class SetUseSimTime(Action):
    """`set_use_sim_time: {value: true}`: `use_sim_time` for every later node in the scope."""

    def __init__(self, *, value: Typed, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.value = value

    @classmethod
    def parse(cls, entity: Entity, parser: Parser) -> tuple[type[Action], SetUseSimTimeKwargs]:
        _, kwargs = super().parse(entity, parser)
        kwargs['value'] = parser.typed(entity, 'value', bool, optional=False)
        return cls, kwargs

    def execute(self, context: Any) -> None:
        context.ros.params.append(('use_sim_time', self.value.perform(context)))
