"""`ExecuteProcess` (`executable`) and launch_ros's `Node` (`node`): the actions that become
processes. Both are ExecuteLocal (zros.launch.actions.execute_local) over an Executable made of
their own arguments.

`Node` is `ExecuteProcess` plus what launch_ros adds: the command is
`python -m zros run PKG EXEC [args] --ros-args -r __node:=NAME -r __ns:=/NS -r from:=to
--params-file ... [ros_args]`, so a node runs exactly as it would under `zros run` (a node
without a package runs an executable from PATH the same way). Everything is checked while the
launch is resolved (package, executable, names, parameter files), so one bad node stops the
launch before any process starts.
"""
from __future__ import annotations

import sys
from pathlib import Path
from typing import Any

from zros.errors import InvalidNameError
from zros.launch.action import Action, Parser, launch_tag
from zros.launch.actions.execute_local import (DEFAULT_SIGKILL_TIMEOUT, DEFAULT_SIGTERM_TIMEOUT, ExecuteLocal,
                                               ExecuteLocalKwargs, check_program, process_label)
from zros.launch.actions.group import join_namespace
from zros.launch.descriptions.executable import CommandLine, Executable
from zros.launch.context import RosScope
from zros.launch.entity import Entity, Scalar
from zros.launch.errors import LaunchFileError, LaunchTypeError, Origin
from zros.launch.parameters import ParamEntry, param_entries, yaml_param_entries
from zros.launch.plan import GeneratedParams, LogMessage, NodeInfo, ParamsFile, ProcessSpec
from zros.launch.origin import origin_here
from zros.launch.template import Text, parse, perform

__all__ = ['ExecuteProcess', 'Node', 'CommandLine', 'DEFAULT_SIGTERM_TIMEOUT', 'DEFAULT_SIGKILL_TIMEOUT',
           'check_program', 'process_label']   # (the last two re-exported from execute_local)

class ExecuteKwargs(ExecuteLocalKwargs, total=False):
    cmd: CommandLine
    name: Text | None
    cwd: Text | None
    prefix: CommandLine | None
    additional_env: list[tuple[Text, Text]]


@launch_tag('executable')
class ExecuteProcess(ExecuteLocal):
    """`ExecuteProcess(cmd=[...], name, cwd, env, additional_env, prefix, ...)` plus every
    ExecuteLocal keyword; YAML `executable: {cmd, name, cwd, launch-prefix, shell, output,
    respawn, ..., on_exit: shutdown, env: [{name, value}]}`.

    It is ExecuteLocal over an Executable made of `cmd`, `name`, `cwd`, `env`,
    `additional_env` and `prefix`. Python's `cmd` is a list with one argument per item; YAML's
    is one string, split like a shell would after substitution.
    """

    def __init__(self, *, cmd: Any = None, name: Any = None, cwd: Any = None, env: Any = None,
                 additional_env: Any = None, prefix: Any = None, origin: Origin | None = None,
                 **kwargs: Any) -> None:
        origin = origin or origin_here(type(self).__name__)
        description = Executable(cmd=cmd, name=name, cwd=cwd, env=env, additional_env=additional_env,
                                 prefix=prefix, origin=origin)
        super().__init__(process_description=description, origin=origin, **kwargs)

    # -- parsing -----------------------------------------------------------------------------
    @classmethod
    def parse(cls, entity: Entity, parser: Parser) -> tuple[type[Action], ExecuteKwargs]:
        _, kwargs = cls.parse_process(entity, parser)
        kwargs['cmd'] = CommandLine.yaml(parser.text(entity, 'cmd'))
        kwargs['name'] = parser.text(entity, 'name', optional=True)
        kwargs['shell'] = parser.typed(entity, 'shell', bool)
        return cls, kwargs

    @classmethod
    def parse_process(cls, entity: Entity, parser: Parser) -> tuple[type[Action], ExecuteKwargs]:
        """The attributes `executable` and `node` share."""
        from zros.launch.actions.shutdown import Shutdown
        _, kwargs = super().parse(entity, parser)
        kwargs['cwd'] = parser.text(entity, 'cwd', optional=True)
        kwargs['prefix'] = CommandLine.yaml(parser.text(entity, 'launch-prefix', optional=True))
        kwargs['output'] = parser.text(entity, 'output', optional=True)
        kwargs['respawn'] = parser.typed(entity, 'respawn', bool)
        kwargs['respawn_delay'] = parser.typed(entity, 'respawn_delay', float)
        kwargs['respawn_max_retries'] = parser.typed(entity, 'respawn_max_retries', int)
        kwargs['sigterm_timeout'] = parser.typed(entity, 'sigterm_timeout', float)
        kwargs['sigkill_timeout'] = parser.typed(entity, 'sigkill_timeout', float)
        kwargs['emulate_tty'] = parser.typed(entity, 'emulate_tty', bool)
        on_exit = entity.get_attr('on_exit', optional=True)
        if on_exit is not None:
            if on_exit != 'shutdown':
                raise entity.error('on_exit', f"the only supported action is 'shutdown', got '{on_exit}'")
            kwargs['on_exit'] = [Shutdown(origin=entity.origin_of('on_exit'))]
        env = []
        for item in entity.get_attr('env', data_type=list[Entity], optional=True) or []:
            env.append((parser.text(item, 'name'), parser.text(item, 'value', data_type=Scalar)))
            item.assert_complete()
        kwargs['additional_env'] = env
        return cls, kwargs


# -- node -------------------------------------------------------------------------------------
def _set_dotted(tree: dict, name: str, value: Any, origin: Origin) -> None:
    parts = name.split('.')
    if not all(parts):
        raise LaunchFileError(origin, f"invalid parameter name '{name}'")
    for part in parts[:-1]:
        child = tree.get(part)
        if not isinstance(child, dict):
            child = tree[part] = {}
        tree = child
    tree[parts[-1]] = value


def remap_pairs(owner: Action, remappings: Any) -> list[tuple[Text, Text]]:
    """Python `remappings=[(from, to), ...]` as Text pairs; a LaunchTypeError (a TypeError, as
    launch_ros raises) for anything else, such as a dict."""
    if isinstance(remappings, (dict, str)):
        raise LaunchTypeError(owner.origin.with_key('remappings'),
                              f'expected a list of (from, to) pairs, got {type(remappings).__name__}')
    pairs = []
    for rule in remappings or []:
        if isinstance(rule, (dict, str)):
            raise LaunchTypeError(owner.origin.with_key('remappings'), f'expected (from, to) pairs, got {rule!r:.60}')
        try:
            source, target = rule
        except (TypeError, ValueError):
            raise LaunchTypeError(owner.origin.with_key('remappings'),
                                  f'expected (from, to) pairs, got {rule!r:.60}') from None
        pairs.append((owner._text(source, 'remappings'), owner._text(target, 'remappings')))
    return pairs


#: The package of ROS's component containers: a Node of it is a container of this launch.
CONTAINER_PACKAGE = 'rclcpp_components'


class NodeKwargs(ExecuteKwargs, total=False):
    package: Text | None
    executable: Text
    exec_name: Text | None
    namespace: Text | None
    arguments: CommandLine | None
    ros_arguments: CommandLine | None
    parameters: tuple[ParamEntry, ...]
    remappings: list[tuple[Text, Text]]


@launch_tag('node')
class Node(ExecuteProcess):
    """`Node(package, executable, name, namespace, exec_name, parameters, remappings,
    arguments, ros_arguments, ...)` plus every ExecuteProcess keyword but `cmd` and `shell`;
    YAML `node: {pkg, exec, name, namespace, exec_name, args, ros_args, param, remap, ...}`.

    Without a package, `executable` is a program on PATH, run with the same `--ros-args`.
    """

    #: launch_ros's placeholders in `node_name` for a name or namespace neither the node nor
    #: its scope gives (the process keeps its own).
    UNSPECIFIED_NODE_NAME = '<node_name_unspecified>'
    UNSPECIFIED_NODE_NAMESPACE = '<node_namespace_unspecified>'

    def __init__(self, *, executable: Any, package: Any = None, name: Any = None, namespace: Any = None,
                 exec_name: Any = None, parameters: Any = None, remappings: Any = None, arguments: Any = None,
                 ros_arguments: Any = None, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.package = self._optional_text(package, 'package')
        self.executable = self._text(executable, 'executable')
        self.given_name = self._optional_text(name, 'name')
        self.namespace = self._optional_text(namespace, 'namespace')
        self.__expanded_node_name = self.UNSPECIFIED_NODE_NAME
        self.__expanded_node_namespace = self.UNSPECIFIED_NODE_NAMESPACE
        self.__final_node_name: str | None = None
        self.__expanded_remappings: list[tuple[str, str]] | None = None
        if exec_name is not None:
            self.process_description.name = self._text(exec_name, 'exec_name')
        self.arguments = CommandLine.of(arguments, self.origin.with_key('arguments')) if arguments is not None else None
        self.ros_arguments = (CommandLine.of(ros_arguments, self.origin.with_key('ros_arguments'))
                              if ros_arguments is not None else None)
        if parameters is not None and not isinstance(parameters, (list, tuple)):
            raise LaunchTypeError(self.origin.with_key('parameters'), 'expected a list of parameter dicts and '
                                  f'files, got {type(parameters).__name__}')
        self.parameters = parameters if isinstance(parameters, tuple) and all(
            isinstance(p, ParamEntry) for p in parameters) else param_entries(parameters, self.origin.with_key('parameters'))
        self.remappings = remappings if isinstance(remappings, list) and all(
            isinstance(r, tuple) and isinstance(r[0], Text) for r in remappings) else remap_pairs(self, remappings)

    @classmethod
    def parse(cls, entity: Entity, parser: Parser) -> tuple[type[Action], NodeKwargs]:
        _, kwargs = cls.parse_process(entity, parser)
        kwargs['package'] = parser.text(entity, 'pkg', optional=True)
        kwargs['executable'] = parser.text(entity, 'exec')
        kwargs['exec_name'] = parser.text(entity, 'exec_name', optional=True)
        kwargs['name'] = parser.text(entity, 'name', optional=True)
        kwargs['namespace'] = parser.text(entity, 'namespace', optional=True)
        kwargs['arguments'] = CommandLine.yaml(parser.text(entity, 'args', optional=True, data_type=Scalar))
        kwargs['ros_arguments'] = CommandLine.yaml(parser.text(entity, 'ros_args', optional=True))
        kwargs['parameters'] = yaml_param_entries(entity, parser)
        remaps = []
        for item in entity.get_attr('remap', data_type=list[Entity], optional=True) or []:
            remaps.append((parser.text(item, 'from'), parser.text(item, 'to')))
            item.assert_complete()
        kwargs['remappings'] = remaps
        return cls, kwargs

    # -- resolution ----------------------------------------------------------------------------
    def resolve_names(self, context: Any) -> tuple[str | None, str | None]:
        """The node name and its absolute namespace, validated; None for one neither this node
        nor its scope gives (the node keeps its own)."""
        from zros.names import validate_namespace, validate_node_name
        name = None
        if self.given_name is not None:
            name = self.given_name.perform(context)
            try:
                validate_node_name(name)
            except InvalidNameError as exc:
                raise LaunchFileError(self.given_name.origin, str(exc)) from None
        base = RosScope.of(context).namespace
        if self.namespace is None and not base:
            return name, None
        namespace = join_namespace(base or '/', self.namespace.perform(context)) if self.namespace is not None else base
        try:
            validate_namespace(namespace)
        except InvalidNameError as exc:
            origin = self.namespace.origin if self.namespace is not None else self.origin
            raise LaunchFileError(origin, str(exc)) from None
        return name, namespace

    def _perform_substitutions(self, context: Any) -> None:
        """launch_ros's step before a node starts, which its users read back: the expanded
        name and namespace (`node_name`, `expanded_node_namespace`,
        `is_node_name_fully_specified()`) and remapping rules (`expanded_remapping_rules`).
        `execute` starts the process from these same values."""
        name, namespace = self.resolve_names(context)
        self.__expanded_node_name = name if name is not None else self.UNSPECIFIED_NODE_NAME
        self.__expanded_node_namespace = namespace if namespace is not None else self.UNSPECIFIED_NODE_NAMESPACE
        self.__final_node_name = f"{self.__expanded_node_namespace.rstrip('/')}/{self.__expanded_node_name}"
        self.__expanded_remappings = self.remap_rules(context) or None

    @property
    def node_name(self) -> str:
        """The fully qualified node name, with launch_ros's placeholders for a part not given.

        Raises:
            RuntimeError: the node has not been executed yet.
        """
        if self.__final_node_name is None:
            raise RuntimeError("cannot access 'node_name' before executing action")
        return self.__final_node_name

    @property
    def expanded_node_namespace(self) -> str:
        return self.__expanded_node_namespace

    @property
    def expanded_remapping_rules(self) -> list[tuple[str, str]] | None:
        return self.__expanded_remappings

    def is_node_name_fully_specified(self) -> bool:
        """Whether both the name and the namespace are known (launch_ros tracks only those)."""
        return all(part not in self.node_name for part in (self.UNSPECIFIED_NODE_NAME, self.UNSPECIFIED_NODE_NAMESPACE))

    def _counted_name(self, context: Any) -> str | None:
        """The full name launch_ros counts this node under: only one fully specified."""
        return self.node_name if self.is_node_name_fully_specified() else None

    def _count_node_name(self, context: Any) -> None:
        """launch_ros's duplicate-name warning: two nodes of one name confuse the ROS graph."""
        fqn = self._counted_name(context)
        if fqn is None:
            return
        context.node_names[fqn] += 1
        count = context.node_names[fqn]
        if count > 1:
            context.emit(LogMessage('WARNING', f'there are now at least {count} nodes with the name {fqn} '
                                               'created within this launch context', self.origin))

    def remap_rules(self, context: Any) -> list[tuple[str, str]]:
        """The scope's remappings (SetRemap), then this node's, evaluated."""
        rules = [*RosScope.of(context).remaps, *((s.perform(context), t.perform(context)) for s, t in self.remappings)]
        for source, target in rules:
            if not source or not target:
                raise LaunchFileError(self.origin.with_key('remap'), f"remapping '{source}:={target}' "
                                      "needs both 'from' and 'to'")
        return rules

    def ros_arguments_for(self, context: Any, name: str | None, namespace: str) -> list[str]:
        """`-r __node:=`, `-r __ns:=`, then the remapping rules."""
        ros: list[str] = []
        if name is not None:
            ros += ['-r', f'__node:={name}']
        if namespace != '/':
            ros += ['-r', f'__ns:={namespace}']
        for source, target in self.__expanded_remappings or []:
            ros += ['-r', f'{source}:={target}']
        return ros

    def execute(self, context: Any) -> list[Action]:
        executable = self.executable.perform(context)
        options = self.process_options(context)
        if self.package is not None:
            package = self.package.perform(context)
            _check_node_executable(package, executable, self.package.origin, self.executable.origin)
            program = [sys.executable, '-m', 'zros', 'run', package, executable]
        else:
            package = ''
            check_program(executable, options, context, self.executable.origin)
            program = [executable]
        self._perform_substitutions(context)
        name, namespace = self.resolve_names(context)
        namespace = namespace or '/'
        ros = self.ros_arguments_for(context, name, namespace)
        self._count_node_name(context)
        fqn = f"{'' if namespace == '/' else namespace}/{name or executable}"
        if package == CONTAINER_PACKAGE:   # Nav2's bringup starts its container this way
            context.containers.add(fqn)
        params = self.param_sources(context, fqn)
        user_args = self.arguments.perform(context) if self.arguments is not None else []
        head = [*self.process_description.prefix_args(context, executable), *program, *user_args]
        if self.ros_arguments is not None:   # as launch_ros: the user's ROS arguments come first
            head += ['--ros-args', *self.ros_arguments.perform(context)]
        if ros or params:
            head += ['--ros-args', *ros]
        label = self.process_description.label(context, executable)
        return self.emit_process(context, ProcessSpec(
            label=process_label(label), cmd_head=tuple(head), params=tuple(params),
            node=NodeInfo(package, executable, name, namespace), **options))

    # -- parameters ----------------------------------------------------------------------------
    def param_sources(self, context: Any, fqn: str) -> list:
        """Parameter sources in order: the scope's `SetParameter`s and `SetParametersFromFile`s,
        then this node's entries; consecutive inline values share one generated file, files
        stay in place."""
        sources: list = []
        inline: dict = {}

        def flush() -> None:
            nonlocal inline
            if inline:
                sources.append(GeneratedParams({'/**': {'ros__parameters': inline}}))
                inline = {}

        for item in RosScope.of(context).params:
            if isinstance(item, tuple):
                _set_dotted(inline, item[0], item[1], self.origin)
            else:   # SetParametersFromFile's file
                flush()
                sources.append(self._params_file(ParamEntry(None, None, (), Text.of(item, self.origin), None,
                                                            self.origin), context, fqn))
        for entry in self.parameters:
            if entry.path is not None:
                flush()
                sources.append(self._params_file(entry, context, fqn))
            else:
                self._inline(entry, '', inline, context)
        flush()
        return sources

    def _inline(self, entry: ParamEntry, prefix: str, tree: dict, context: Any) -> None:
        name = prefix + entry.name.perform(context)
        if entry.value is not None:
            _set_dotted(tree, name, entry.value.perform(context), entry.name.origin)
        for child in entry.nested:
            self._inline(child, name + '.', tree, context)

    def _params_file(self, entry: ParamEntry, context: Any, fqn: str) -> ParamsFile | GeneratedParams:
        from zros.launch.files import read_text
        from zros.parameter import ParameterFileError, load_parameter_file
        import yaml
        raw = entry.path.perform(context)
        path = Path(raw)
        if not path.is_absolute():
            beside = Path(context.current_file).parent / path if context.current_file else path
            path = beside if beside.is_file() else Path.cwd() / path
        if not path.is_file():
            raise LaunchFileError(entry.path.origin, f"no such parameter file '{raw}'")
        try:
            text = read_text(str(path), 'parameter file')
            load_parameter_file(str(path), fqn)
        except (ParameterFileError, LaunchFileError) as exc:
            raise LaunchFileError(entry.path.origin, str(exc)) from None
        if entry.allow_substs is not None and entry.allow_substs.perform(context):
            try:
                substituted = perform(parse(text), context)
                document = yaml.safe_load(substituted)
            except Exception as exc:  # noqa: BLE001 - substitution or YAML error, reported with the key
                raise LaunchFileError(entry.path.origin, f"in '{path}' with allow_substs: {exc}") from None
            return GeneratedParams(document or {})
        return ParamsFile(str(path.resolve()))


def _check_node_executable(package: str, executable: str, package_origin: Origin, exec_origin: Origin) -> None:
    from zros.ament_index_python.executables import Executables
    from zros.errors import with_suggestion
    index = Executables()
    packages = index.packages()
    if package not in packages:
        raise LaunchFileError(package_origin, with_suggestion(f"package '{package}' not found", package, packages,
                                                              otherwise=f" (packages: {', '.join(packages)})"))
    executables = index.of(package)
    if index.name(package, executable) is None:
        raise LaunchFileError(exec_origin, with_suggestion(
            f"no executable '{executable}' in package '{package}'", executable, executables,
            otherwise=f" (executables: {', '.join(executables) or 'none'})"))
