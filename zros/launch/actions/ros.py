"""launch_ros's scope actions: `SetParameter` (`set_parameter`), `SetRemap` (`set_remap`),
`SetUseSimTime` (`set_use_sim_time`), `SetParametersFromFile` (`set_parameters_from_file`),
`SetROSLogDir` (`set_ros_log_dir`): what every later node in the scope gets."""
from __future__ import annotations

import os
from typing import Any

from zros.launch.action import Action, ActionKwargs, Parser, launch_tag
from zros.launch.context import RosScope
from zros.launch.entity import Entity
from zros.launch.parameters import ParamValue
from zros.launch.template import Text, Typed

__all__ = ['SetParameter', 'SetRemap', 'SetUseSimTime', 'SetParametersFromFile', 'SetROSLogDir']


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
        self.param_value = value if isinstance(value, ParamValue) else ParamValue.of(value, self.origin.with_key('value'))

    @classmethod
    def parse(cls, entity: Entity, parser: Parser) -> tuple[type[Action], SetParameterKwargs]:
        _, kwargs = super().parse(entity, parser)
        kwargs['name'] = parser.text(entity, 'name')
        kwargs['value'] = ParamValue.from_entity(entity)
        return cls, kwargs

    def execute(self, context: Any) -> None:
        RosScope.of(context).add_param((self.name.perform(context), self.param_value.perform(context)))

    @property
    def value(self) -> Any:
        """launch_ros's view of the value: text as substitutions, other values as given."""
        return self.param_value.as_given()


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
    later node in the scope, and the launch's ROS time (ROSTimer's) is sim time from then on."""

    def __init__(self, value: Any, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.value = self._typed(value, bool, 'value')

    @classmethod
    def parse(cls, entity: Entity, parser: Parser) -> tuple[type[Action], SetUseSimTimeKwargs]:
        _, kwargs = super().parse(entity, parser)
        kwargs['value'] = parser.typed(entity, 'value', bool, optional=False)
        return cls, kwargs

    def execute(self, context: Any) -> None:
        value = self.value.perform(context)
        RosScope.of(context).add_param(('use_sim_time', value))
        # launch_ros sets it on its own node too, whose clock times ROSTimers: launch-wide
        context.launch_use_sim_time = value


class PathKwargs(ActionKwargs, total=False):
    path: Text


class _PathAction(Action):
    """A launch_ros scope action given one path, under the keyword and YAML attribute `KEY`
    (`SetParametersFromFile(filename)`, `SetROSLogDir(new_log_dir)`); kept as `self.path`."""

    KEY = ''

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        value = args[0] if args else kwargs.pop(self.KEY)
        super().__init__(**kwargs)
        self.path = self._text(value, self.KEY)

    @classmethod
    def parse(cls, entity: Entity, parser: Parser) -> tuple[type[Action], PathKwargs]:
        _, kwargs = super().parse(entity, parser)
        kwargs[cls.KEY] = parser.text(entity, cls.KEY)
        return cls, kwargs


@launch_tag('set_parameters_from_file')
class SetParametersFromFile(_PathAction):
    """`SetParametersFromFile(filename)`; YAML `set_parameters_from_file: {filename}`: a ROS 2
    parameter file for every later node in the scope, passed before the node's own parameters
    (each node reads its own entries and the wildcards from it)."""

    KEY = 'filename'

    def execute(self, context: Any) -> None:
        RosScope.of(context).add_param(self.path.perform(context))


@launch_tag('set_ros_log_dir')
class SetROSLogDir(_PathAction):
    """`SetROSLogDir(new_log_dir)`; YAML `set_ros_log_dir: {new_log_dir}`: `ROS_LOG_DIR` for the
    processes started later in the scope. A relative directory goes under the current ROS log
    directory (the launch environment's `ROS_LOG_DIR`, else `ROS_HOME`/log, else ~/.ros/log).
    Like every environment change in zros's launch it changes the launch's environment, not the
    launching process's `os.environ`."""

    KEY = 'new_log_dir'

    @property
    def log_dir(self) -> Any:
        """launch_ros's view: the directory as substitutions."""
        return self.path.substitutions()

    def execute(self, context: Any) -> None:
        from zros.logging import get_logging_directory
        current = get_logging_directory(context.environment)
        context.environment['ROS_LOG_DIR'] = os.path.join(current, self.path.perform(context))
