"""`executable` and `node`: the tags that become processes.

`node` is `executable` plus what launch_ros adds: the command is
`python -m zros run PKG EXEC [args] --ros-args -r __node:=NAME -r __ns:=/NS -r from:=to
--params-file ... [ros_args]`, so a node runs exactly as it would under `zros run`.
Everything is checked while the launch is resolved (package, executable, names, parameter
files), so one bad node stops the launch before any process starts.
"""
from __future__ import annotations

import os
import shlex
import shutil
import sys
from pathlib import Path
from typing import Any, NamedTuple

from zros.errors import InvalidNameError
from zros.launch.actions import Action, ActionKwargs, Parser, launch_tag
from zros.launch.actions.group import join_namespace
from zros.launch.actions.ros import ParamValue
from zros.launch.entity import Entity, Scalar
from zros.launch.errors import LaunchFileError, Origin
from zros.launch.plan import OUTPUT_MODES, GeneratedParams, NodeInfo, ParamsFile, ProcessSpec
from zros.launch.substitutions import Text, Typed, perform, parse

__all__ = ['ExecuteProcess', 'Node', 'DEFAULT_SIGTERM_TIMEOUT', 'DEFAULT_SIGKILL_TIMEOUT']

DEFAULT_SIGTERM_TIMEOUT = 5.0
DEFAULT_SIGKILL_TIMEOUT = 5.0


class ExecuteKwargs(ActionKwargs, total=False):
    cmd: Text
    label: Text | None
    cwd: Text | None
    prefix: Text | None
    output: Text | None
    respawn: Typed | None
    respawn_delay: Typed | None
    respawn_max_retries: Typed | None
    sigterm_timeout: Typed | None
    sigkill_timeout: Typed | None
    shell: Typed | None
    emulate_tty: Typed | None
    on_exit_shutdown: bool
    env: list[tuple[Text, Text]]


def _split(text: str, origin: Origin) -> list[str]:
    try:
        return shlex.split(text)
    except ValueError as exc:
        raise LaunchFileError(origin, f'cannot split {text!r} into arguments: {exc}') from None


@launch_tag('executable')
class ExecuteProcess(Action):
    """`executable: {cmd, cwd, name, launch-prefix, output, respawn, respawn_delay,
    respawn_max_retries, sigterm_timeout, sigkill_timeout, shell, emulate_tty, on_exit, env}`.

    `cmd` is split like a shell would (quotes group words) after substitution; with
    `shell: true` it is run by /bin/sh as written.
    """

    # attributes `parse_process` reads; `node` does not take `cmd` or `shell`
    _COMMON = ('cwd', 'launch-prefix', 'output', 'respawn', 'respawn_delay', 'respawn_max_retries',
               'sigterm_timeout', 'sigkill_timeout', 'emulate_tty', 'on_exit', 'env')

    def __init__(self, *, cmd: Text | None = None, label: Text | None = None, cwd: Text | None = None,
                 prefix: Text | None = None, output: Text | None = None, respawn: Typed | None = None,
                 respawn_delay: Typed | None = None, respawn_max_retries: Typed | None = None,
                 sigterm_timeout: Typed | None = None, sigkill_timeout: Typed | None = None,
                 shell: Typed | None = None, emulate_tty: Typed | None = None, on_exit_shutdown: bool = False,
                 env: list[tuple[Text, Text]] | None = None, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.cmd, self.label, self.cwd, self.prefix, self.output = cmd, label, cwd, prefix, output
        self.respawn, self.respawn_delay, self.respawn_max_retries = respawn, respawn_delay, respawn_max_retries
        self.sigterm_timeout, self.sigkill_timeout = sigterm_timeout, sigkill_timeout
        self.shell, self.emulate_tty = shell, emulate_tty
        self.on_exit_shutdown = on_exit_shutdown
        self.env = env or []

    # -- parsing -----------------------------------------------------------------------------
    @classmethod
    def parse(cls, entity: Entity, parser: Parser) -> tuple[type[Action], ExecuteKwargs]:
        _, kwargs = cls.parse_process(entity, parser)
        kwargs['cmd'] = parser.text(entity, 'cmd')
        kwargs['label'] = parser.text(entity, 'name', optional=True)
        kwargs['shell'] = parser.typed(entity, 'shell', bool)
        return cls, kwargs

    @classmethod
    def parse_process(cls, entity: Entity, parser: Parser) -> tuple[type[Action], ExecuteKwargs]:
        """The attributes `executable` and `node` share."""
        _, kwargs = super().parse(entity, parser)
        kwargs['cwd'] = parser.text(entity, 'cwd', optional=True)
        kwargs['prefix'] = parser.text(entity, 'launch-prefix', optional=True)
        output = parser.text(entity, 'output', optional=True)
        if output is not None and len(output.template) == 1 and isinstance(output.template[0], str) \
                and output.template[0] not in OUTPUT_MODES:
            raise entity.error('output', f"expected one of {', '.join(OUTPUT_MODES)}, got '{output.template[0]}'")
        kwargs['output'] = output
        kwargs['respawn'] = parser.typed(entity, 'respawn', bool)
        kwargs['respawn_delay'] = cls._non_negative(parser.typed(entity, 'respawn_delay', float))
        kwargs['respawn_max_retries'] = parser.typed(entity, 'respawn_max_retries', int)
        kwargs['sigterm_timeout'] = cls._non_negative(parser.typed(entity, 'sigterm_timeout', float))
        kwargs['sigkill_timeout'] = cls._non_negative(parser.typed(entity, 'sigkill_timeout', float))
        kwargs['emulate_tty'] = parser.typed(entity, 'emulate_tty', bool)
        on_exit = entity.get_attr('on_exit', optional=True)
        if on_exit is not None and on_exit != 'shutdown':
            raise entity.error('on_exit', f"the only supported action is 'shutdown', got '{on_exit}'")
        kwargs['on_exit_shutdown'] = on_exit == 'shutdown'
        env = []
        for item in entity.get_attr('env', data_type=list[Entity], optional=True) or []:
            env.append((parser.text(item, 'name'), parser.text(item, 'value', data_type=Scalar)))
            item.assert_complete()
        kwargs['env'] = env
        return cls, kwargs

    @staticmethod
    def _non_negative(value: Typed | None) -> Typed | None:
        if value is not None and not isinstance(value.value, Text) and value.value < 0:
            raise LaunchFileError(value.origin, f'expected a non-negative number, got {value.value:g}')
        return value

    # -- resolution --------------------------------------------------------------------------
    def _number(self, value: Typed | None, default: Any, context: Any) -> Any:
        if value is None:
            return default
        result = value.perform(context)
        if isinstance(result, float) and result < 0:
            raise LaunchFileError(value.origin, f'expected a non-negative number, got {result:g}')
        return result

    def _timeout_default(self, name: str, fallback: float, context: Any) -> float:
        """launch's rule: the `sigterm_timeout` / `sigkill_timeout` launch configurations are
        the defaults, so `zros launch f.yaml sigterm_timeout:=10` changes every process."""
        text = context.configurations.get(name)
        if text is None:
            return fallback
        try:
            return float(text)
        except ValueError:
            raise LaunchFileError(self.origin, f"launch configuration '{name}' must be a number, got '{text}'") from None

    def process_options(self, context: Any) -> dict[str, Any]:
        """ProcessSpec fields common to both tags, resolved."""
        output = os.environ.get('OVERRIDE_LAUNCH_PROCESS_OUTPUT') or (
            self.output.perform(context) if self.output is not None else 'log')
        if output not in OUTPUT_MODES:
            origin = self.output.origin if self.output is not None else self.origin
            raise LaunchFileError(origin, f"expected one of {', '.join(OUTPUT_MODES)}, got '{output}'")
        env_changes = dict(context.environment_changes())
        for name, value in self.env:
            env_changes[name.perform(context)] = value.perform(context)
        cwd = self.cwd.perform(context) if self.cwd is not None else None
        if cwd is not None and not os.path.isdir(cwd):
            raise LaunchFileError(self.cwd.origin, f"no such directory '{cwd}'")
        if self.emulate_tty is not None:
            self.emulate_tty.perform(context)  # accepted for compatibility; output is always line-buffered
        return dict(
            env=tuple(env_changes.items()),
            cwd=cwd,
            output=output,
            respawn=self.respawn.perform(context) if self.respawn is not None else False,
            respawn_delay=self._number(self.respawn_delay, 0.0, context),
            respawn_max_retries=self._number(self.respawn_max_retries, -1, context),
            sigterm_timeout=self._number(self.sigterm_timeout,
                                         self._timeout_default('sigterm_timeout', DEFAULT_SIGTERM_TIMEOUT, context),
                                         context),
            sigkill_timeout=self._number(self.sigkill_timeout,
                                         self._timeout_default('sigkill_timeout', DEFAULT_SIGKILL_TIMEOUT, context),
                                         context),
            on_exit_shutdown=self.on_exit_shutdown,
            origin=self.origin,
        )

    def prefix_args(self, context: Any) -> list[str]:
        """`launch-prefix` (or the `launch-prefix` configuration, as in launch)."""
        if self.prefix is not None:
            return _split(self.prefix.perform(context), self.prefix.origin)
        configured = context.configurations.get('launch-prefix', '')
        return _split(configured, self.origin) if configured else []

    def execute(self, context: Any) -> None:
        text = self.cmd.perform(context)
        shell = self.shell.perform(context) if self.shell is not None else False
        options = self.process_options(context)
        prefix = self.prefix_args(context)
        if shell:
            if not text.strip():
                raise LaunchFileError(self.cmd.origin, 'empty command')
            head = (*prefix, '/bin/sh', '-c', text)
            first = text.split()[:1] or ['sh']
            shell_text = shlex.join(prefix) + ' ' + text if prefix else text
        else:
            argv = _split(text, self.cmd.origin)
            if not argv:
                raise LaunchFileError(self.cmd.origin, 'empty command')
            self._check_program(argv[0], options, context)
            head = (*prefix, *argv)
            first, shell_text = argv, None
        label = self.label.perform(context) if self.label is not None else os.path.basename(first[0])
        context.emit(ProcessSpec(label=_label(label), cmd_head=tuple(head), shell_text=shell_text, **options))

    def _check_program(self, program: str, options: dict, context: Any) -> None:
        env = dict(context.environment)
        env.update({k: v for k, v in options['env'] if v is not None})
        if os.sep in program:
            path = Path(options['cwd'] or '.') / program if not os.path.isabs(program) else Path(program)
            ok = path.is_file() and os.access(path, os.X_OK)
        else:
            ok = shutil.which(program, path=env.get('PATH')) is not None
        if not ok:
            raise LaunchFileError(self.cmd.origin, f"executable '{program}' not found"
                                  + ('' if os.sep in program else ' on PATH'))


def _label(text: str) -> str:
    """A process label usable in output prefixes and log file names."""
    clean = ''.join(c if c.isalnum() or c in '_.-' else '_' for c in text.strip())
    return clean or 'process'


# -- node -------------------------------------------------------------------------------------
class ParamEntry(NamedTuple):
    """One `param:` item: `name`+`value`, `name`+nested `param`, or `from` (+ `allow_substs`)."""

    name: Text | None
    value: ParamValue | None
    nested: tuple['ParamEntry', ...]
    path: Text | None
    allow_substs: Typed | None
    origin: Origin


def _parse_param_entries(entity: Entity, parser: Parser) -> tuple[ParamEntry, ...]:
    entries = []
    for item in entity.get_attr('param', data_type=list[Entity], optional=True) or []:
        if item.has('from'):
            if item.has('name'):
                raise item.error('name', "'name' and 'from' cannot be used together")
            entries.append(ParamEntry(None, None, (), parser.text(item, 'from'),
                                      parser.typed(item, 'allow_substs', bool), item.origin))
        else:
            if not item.has('name'):
                raise item.error(None, "a parameter needs 'name' (with 'value' or nested 'param') or 'from'")
            name = parser.text(item, 'name')
            if item.has('value') and item.has('param'):
                raise item.error('param', "'value' and nested 'param' cannot be used together")
            if item.has('param'):
                entries.append(ParamEntry(name, None, _parse_param_entries(item, parser), None, None, item.origin))
            elif item.has('value'):
                entries.append(ParamEntry(name, ParamValue.from_entity(item, parser), (), None, None, item.origin))
            else:
                raise item.error(None, f"parameter '{name}' needs a 'value' or nested 'param' entries")
        item.assert_complete()
    return tuple(entries)


def _set_dotted(tree: dict, name: str, value: Any, origin: Origin) -> None:
    parts = [p for p in name.split('.')]
    if not all(parts):
        raise LaunchFileError(origin, f"invalid parameter name '{name}'")
    for part in parts[:-1]:
        child = tree.get(part)
        if not isinstance(child, dict):
            child = tree[part] = {}
        tree = child
    tree[parts[-1]] = value


class NodeKwargs(ExecuteKwargs, total=False):
    package: Text
    executable: Text
    node_name: Text | None
    namespace: Text | None
    args: Text | None
    ros_args: Text | None
    params: tuple[ParamEntry, ...]
    remaps: list[tuple[Text, Text]]


@launch_tag('node')
class Node(ExecuteProcess):
    """`node: {pkg, exec, name, namespace, exec_name, args, ros_args, param, remap}` plus every
    `executable` attribute except `cmd` and `shell`."""

    def __init__(self, *, package: Text, executable: Text, node_name: Text | None = None,
                 namespace: Text | None = None, args: Text | None = None, ros_args: Text | None = None,
                 params: tuple[ParamEntry, ...] = (), remaps: list | None = None, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.package, self.executable = package, executable
        self.node_name, self.namespace = node_name, namespace
        self.args, self.ros_args = args, ros_args
        self.params, self.remaps = params, remaps or []

    @classmethod
    def parse(cls, entity: Entity, parser: Parser) -> tuple[type[Action], NodeKwargs]:
        _, kwargs = cls.parse_process(entity, parser)
        kwargs['package'] = parser.text(entity, 'pkg')
        kwargs['executable'] = parser.text(entity, 'exec')
        kwargs['label'] = parser.text(entity, 'exec_name', optional=True)
        kwargs['node_name'] = parser.text(entity, 'name', optional=True)
        kwargs['namespace'] = parser.text(entity, 'namespace', optional=True)
        kwargs['args'] = parser.text(entity, 'args', optional=True, data_type=Scalar)
        kwargs['ros_args'] = parser.text(entity, 'ros_args', optional=True)
        kwargs['params'] = _parse_param_entries(entity, parser)
        remaps = []
        for item in entity.get_attr('remap', data_type=list[Entity], optional=True) or []:
            remaps.append((parser.text(item, 'from'), parser.text(item, 'to')))
            item.assert_complete()
        kwargs['remaps'] = remaps
        return cls, kwargs

    def execute(self, context: Any) -> None:
        from zros.names import validate_namespace, validate_node_name
        package = self.package.perform(context)
        executable = self.executable.perform(context)
        _check_node_executable(package, executable, self.package.origin, self.executable.origin)
        name = None
        if self.node_name is not None:
            name = self.node_name.perform(context)
            try:
                validate_node_name(name)
            except InvalidNameError as exc:
                raise LaunchFileError(self.node_name.origin, str(exc)) from None
        base = context.ros.namespace or '/'
        if self.namespace is not None:
            namespace = join_namespace(base, self.namespace.perform(context))
        else:
            namespace = base
        try:
            validate_namespace(namespace)
        except InvalidNameError as exc:
            origin = self.namespace.origin if self.namespace is not None else self.origin
            raise LaunchFileError(origin, str(exc)) from None

        ros: list[str] = []
        if name is not None:
            ros += ['-r', f'__node:={name}']
        if namespace != '/':
            ros += ['-r', f'__ns:={namespace}']
        for source, target in [*context.ros.remaps,
                               *((s.perform(context), t.perform(context)) for s, t in self.remaps)]:
            if not source or not target:
                raise LaunchFileError(self.origin.with_key('remap'), f"remapping '{source}:={target}' "
                                      "needs both 'from' and 'to'")
            ros += ['-r', f'{source}:={target}']
        fqn = f"{'' if namespace == '/' else namespace}/{name or executable}"
        params = self._param_sources(context, fqn)
        user_args = _split(self.args.perform(context), self.args.origin) if self.args is not None else []
        tail = _split(self.ros_args.perform(context), self.ros_args.origin) if self.ros_args is not None else []
        head = [*self.prefix_args(context), sys.executable, '-m', 'zros', 'run', package, executable, *user_args]
        if ros or params or tail:
            head += ['--ros-args', *ros]
        label = self.label.perform(context) if self.label is not None else executable
        context.emit(ProcessSpec(label=_label(label), cmd_head=tuple(head), params=tuple(params),
                                 cmd_tail=tuple(tail), node=NodeInfo(package, executable, name, namespace),
                                 **self.process_options(context)))

    # -- parameters ----------------------------------------------------------------------------
    def _param_sources(self, context: Any, fqn: str) -> list:
        """Parameter sources in order: the scope's `set_parameter`s, then this node's entries;
        consecutive inline values share one generated file, `from:` files stay in place."""
        sources: list = []
        inline: dict = {}

        def flush() -> None:
            nonlocal inline
            if inline:
                sources.append(GeneratedParams({'/**': {'ros__parameters': inline}}))
                inline = {}

        for name, value in context.ros.params:
            _set_dotted(inline, name, value, self.origin)
        for entry in self.params:
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
            load_parameter_file(str(path), fqn)
        except ParameterFileError as exc:
            raise LaunchFileError(entry.path.origin, str(exc)) from None
        if entry.allow_substs is not None and entry.allow_substs.perform(context):
            text = path.read_text(encoding='utf-8')
            try:
                substituted = perform(parse(text), context)
                document = yaml.safe_load(substituted)
            except Exception as exc:  # noqa: BLE001 - substitution or YAML error, reported with the key
                raise LaunchFileError(entry.path.origin, f"in '{path}' with allow_substs: {exc}") from None
            return GeneratedParams(document or {})
        return ParamsFile(str(path.resolve()))


def _check_node_executable(package: str, executable: str, package_origin: Origin, exec_origin: Origin) -> None:
    from zros.cli.run import list_executables, list_packages
    packages = list_packages()
    if package not in packages:
        raise LaunchFileError(package_origin, f"package '{package}' not found (packages: {', '.join(packages)})")
    executables = list_executables(package)
    if executable not in executables:
        raise LaunchFileError(exec_origin, f"no executable '{executable}' in package '{package}' "
                                           f"(executables: {', '.join(executables) or 'none'})")
