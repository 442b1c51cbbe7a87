"""Parameters (rclpy.parameter): typed values with ROS 2's type rules, and their messages.

Also where parameter overrides are read: `--params-file` YAML in the ROS 2 layout
(`node: ros__parameters: {...}`, with `/**` and `*` wildcards in node names) and
`-p name:=value` values, both YAML-typed as in ROS 2.
"""
from __future__ import annotations

import enum
import fnmatch
import functools
import re
from typing import Any

__all__ = ['Parameter', 'parameter_value_to_python', 'load_parameter_file', 'parameter_dict_from_yaml_file',
           'flatten_parameters',
           'parse_parameter_value', 'get_parameter_value', 'ParameterFileError',
           'ParameterFileNotFoundError']

from zros.errors import ZrosError
from zros.message import register_stand_in


class ParameterFileError(ZrosError):
    """A parameter file that cannot be read; the message names the file."""


class ParameterFileNotFoundError(ParameterFileError, FileNotFoundError):
    """A parameter file that does not exist: also a FileNotFoundError, which is what rclpy's
    parameter_dict_from_yaml_file raises and its callers catch."""


class Parameter:
    """A named, typed parameter value, as rclpy.parameter.Parameter.

    The type is inferred from the value when not given, with ROS 2's rules: an int given for a
    DOUBLE parameter becomes a float, tuples and numpy arrays become lists.

    :param name: The parameter's name (dots separate namespaces).
    :param type_: A Parameter.Type; ``None`` infers it from `value`.
    :param value: The value; ``None`` with no type gives a NOT_SET parameter.
    :raises TypeError: If `type_` is no Parameter.Type, or the value's type cannot be inferred
        (an array mixing element types, a dict).
    :raises ValueError: If the value does not match the given type (as rclpy).
    """
    class Type(enum.IntEnum):
        NOT_SET = 0
        BOOL = 1
        INTEGER = 2
        DOUBLE = 3
        STRING = 4
        BYTE_ARRAY = 5
        BOOL_ARRAY = 6
        INTEGER_ARRAY = 7
        DOUBLE_ARRAY = 8
        STRING_ARRAY = 9

        @classmethod
        def from_parameter_value(cls, value: Any) -> 'Parameter.Type':
            """The type ROS 2 infers for a Python value (rclpy's rules, homogeneous lists)."""
            if value is None:
                return cls.NOT_SET
            if isinstance(value, bool):
                return cls.BOOL
            if isinstance(value, int):
                return cls.INTEGER
            if isinstance(value, float):
                return cls.DOUBLE
            if isinstance(value, str):
                return cls.STRING
            if isinstance(value, (bytes, bytearray)):
                return cls.BYTE_ARRAY
            if hasattr(value, 'tolist') and not isinstance(value, (list, tuple)):
                value = value.tolist()
            if isinstance(value, (list, tuple)):
                if all(isinstance(v, bytes) for v in value):
                    return cls.BYTE_ARRAY
                if all(isinstance(v, bool) for v in value):
                    return cls.BOOL_ARRAY
                if all(isinstance(v, int) and not isinstance(v, bool) for v in value):
                    return cls.INTEGER_ARRAY
                if all(isinstance(v, float) for v in value):
                    return cls.DOUBLE_ARRAY
                if all(isinstance(v, str) for v in value):
                    return cls.STRING_ARRAY
                raise TypeError(f'the elements of a parameter array must all have one type '
                                f'(bool, int, float or str), got {value!r:.80}')
            raise TypeError(f'unsupported parameter value type {type(value).__name__}')

        def check(self, value: Any) -> bool:
            """Whether `value` is of this type (only None is NOT_SET, as rclpy)."""
            try:
                return Parameter.Type.from_parameter_value(value) == self
            except TypeError:
                return False

    def __init__(self, name: str, type_: 'Parameter.Type | None' = None, value: Any = None) -> None:
        if type_ is None:
            type_ = Parameter.Type.from_parameter_value(value)
        try:
            type_ = Parameter.Type(type_)
        except ValueError:
            raise TypeError(f'type must be a Parameter.Type, got {type_!r} (parameter {name})') from None
        if hasattr(value, 'tolist') and not isinstance(value, (list, tuple)):
            value = value.tolist()
        if isinstance(value, tuple):
            value = list(value)
        if type_ == Parameter.Type.DOUBLE and isinstance(value, int) and not isinstance(value, bool):
            value = float(value)
        if type_ == Parameter.Type.DOUBLE_ARRAY and isinstance(value, list):
            value = [float(v) if isinstance(v, int) and not isinstance(v, bool) else v for v in value]
        if not type_.check(value):
            raise ValueError(f"type {type(value).__name__} of value {value!r:.60} does not match "
                            f'parameter type {type_.name} (parameter {name})')
        self._name = name
        self._type = type_
        self._value = value

    @property
    def name(self) -> str:
        """The parameter's name."""
        return self._name

    @property
    def type_(self) -> 'Parameter.Type':
        """The parameter's Parameter.Type."""
        return self._type

    @property
    def value(self) -> Any:
        """The parameter's value as a Python object (lists for arrays)."""
        return self._value

    def get_parameter_value(self):
        """The value as a message.

        :return: An rcl_interfaces/msg/ParameterValue with the type set and the matching field filled.
        """
        from interfaces.rcl_interfaces.msg import ParameterValue
        T = Parameter.Type
        msg = ParameterValue(type=int(self._type))
        field = {T.BOOL: 'bool_value', T.INTEGER: 'integer_value', T.DOUBLE: 'double_value',
                 T.STRING: 'string_value', T.BYTE_ARRAY: 'byte_array_value', T.BOOL_ARRAY: 'bool_array_value',
                 T.INTEGER_ARRAY: 'integer_array_value', T.DOUBLE_ARRAY: 'double_array_value',
                 T.STRING_ARRAY: 'string_array_value'}.get(self._type)
        if field is not None:
            value = self._value
            if self._type == T.BYTE_ARRAY:
                value = b''.join(v if isinstance(v, bytes) else bytes([v]) for v in value) \
                    if isinstance(value, list) else bytes(value)
            setattr(msg, field, value)
        return msg

    def to_parameter_msg(self):
        """The parameter as a message.

        :return: An rcl_interfaces/msg/Parameter (name and ParameterValue).
        """
        from interfaces.rcl_interfaces.msg import Parameter as ParameterMsg
        return ParameterMsg(name=self._name, value=self.get_parameter_value())

    @classmethod
    def from_parameter_msg(cls, msg) -> 'Parameter':
        """Build a Parameter from its message.

        :param msg: An rcl_interfaces/msg/Parameter.
        :return: The parameter, typed as the message says.
        """
        return cls(msg.name, Parameter.Type(msg.value.type), parameter_value_to_python(msg.value))

    def __eq__(self, other: object) -> bool:
        return (isinstance(other, Parameter) and (self._name, self._type, self._value)
                == (other._name, other._type, other._value))

    def __hash__(self) -> int:
        # equal parameters hash alike; a list value is hashed as the tuple of its elements
        value = tuple(self._value) if isinstance(self._value, list) else self._value
        return hash((self._name, self._type, value))

    def __repr__(self) -> str:
        return f'Parameter(name={self._name!r}, type_={self._type.name}, value={self._value!r})'


# rclpy code builds ParameterEvent messages from Parameter objects; a Parameter field takes one
# as its message
register_stand_in('rcl_interfaces/msg/Parameter', Parameter, Parameter.to_parameter_msg)


def parameter_value_to_python(msg) -> Any:
    """The Python value of an rcl_interfaces/msg/ParameterValue (None for NOT_SET).

    Raises:
        RuntimeError: the message's `type` is no ParameterType (as rclpy).
    """
    T = Parameter.Type
    try:
        kind = T(msg.type)
    except ValueError:
        raise RuntimeError(f'unexpected parameter type {msg.type}') from None
    if kind == T.NOT_SET:
        return None
    if kind == T.BOOL:
        return bool(msg.bool_value)
    if kind == T.INTEGER:
        return int(msg.integer_value)
    if kind == T.DOUBLE:
        return float(msg.double_value)
    if kind == T.STRING:
        return msg.string_value
    if kind == T.BYTE_ARRAY:
        return list(msg.byte_array_value)
    if kind == T.BOOL_ARRAY:
        return [bool(b) for b in msg.bool_array_value]
    if kind == T.INTEGER_ARRAY:
        return [int(v) for v in msg.integer_array_value]
    if kind == T.DOUBLE_ARRAY:
        return [float(v) for v in msg.double_array_value]
    return list(msg.string_array_value)


def get_parameter_value(string_value: str) -> Any:
    """rclpy's: the ParameterValue message a `-p name:=value` text stands for, typed by YAML
    (`'42'` an integer, `'[1.0, 2.0]'` a double array; what YAML cannot type, or a list of
    mixed types, is a string).

    :param string_value: the text.
    :return: an rcl_interfaces/msg/ParameterValue.
    """
    value = parse_parameter_value(string_value)
    try:
        return Parameter('', value=value).get_parameter_value()
    except Exception:  # noqa: BLE001 - a list of mixed types: rclpy keeps the text
        return Parameter('', value=string_value).get_parameter_value()


def parse_parameter_value(text: str) -> Any:
    """A `-p name:=value` value, typed by YAML as ROS 2 does ('1' int, '1.0' float, 'true' bool)."""
    import yaml
    try:
        value = yaml.safe_load(text)
    except yaml.YAMLError:
        return text
    if value is None or isinstance(value, dict):
        return text  # as ros2 param: what YAML cannot type is a string
    return value


def _flatten(prefix: str, tree: dict, out: dict) -> None:
    for key, value in tree.items():
        name = f'{prefix}.{key}' if prefix else str(key)
        if isinstance(value, dict):
            _flatten(name, value, out)
        else:
            out[name] = value


def flatten_parameters(tree: dict) -> dict[str, Any]:
    """`{a: {b: 1}}` -> `{'a.b': 1}`: nested YAML maps give dotted parameter names."""
    out: dict[str, Any] = {}
    _flatten('', tree, out)
    return out


def _node_pattern_matches(pattern: str, node_fqn: str) -> bool:
    """ROS 2's node-name wildcards: `*` one token, `**` any number. A key is read from the
    root as rcl reads it, leading '/' or not: `node2` and `*` match /node2, not /ns/node2."""
    if pattern in ('/**', '**'):
        return True
    regex = ''
    for token in pattern.strip('/').split('/'):
        if token == '**':
            regex += r'(/[^/]+)*'
        else:
            regex += '/' + fnmatch.translate(token).replace(r'(?s:', '(?:').replace(r')\Z', ')').replace('.*', '[^/]*')
    return re.fullmatch(regex, node_fqn) is not None


def load_parameter_file(path: str, node_fqn: str, *, use_wildcard: bool = True) -> dict[str, Any]:
    """Parameters for `node_fqn` from a ROS 2 parameter YAML file, in file order
    (`use_wildcard=False` ignores `/**` entries, as `ros2 param load --no-use-wildcard`)."""
    values: dict[str, Any] = {}
    for node_key, params in _parameter_entries(path):
        if not use_wildcard and node_key in ('/**', '**'):
            continue
        if _node_pattern_matches(node_key, node_fqn):
            _flatten('', params, values)
    return values


def parameter_dict_from_yaml_file(parameter_file: str, use_wildcard: bool = False,
                                  target_nodes: list[str] | None = None, namespace: str = '') -> dict[str, Any]:
    """rclpy's: the rcl_interfaces/msg/Parameter messages of a parameter file, by name.

    Every node entry counts (what AsyncParameterClient.load_parameter_file sends to its one
    remote node), or only those of `target_nodes` (names as the file writes them); the `/**`
    entry only with use_wildcard, and first, so a node's own entry overrides it. `namespace`
    is prefixed to every name as it is (`'arm.'`).

    Raises:
        ParameterFileError: the file cannot be read, a target node has no entry, or nothing
            is selected.
    """
    entries = _parameter_entries(parameter_file)
    wanted = None if target_nodes is None else [node.strip('/') for node in target_nodes]
    present = {key.strip('/') for key, _ in entries}
    missing = [node for node in wanted or () if node not in present]
    if missing:
        raise ParameterFileError(f"{parameter_file}: no parameters for node(s) {', '.join(missing)} "
                                 f"(the file has {', '.join(sorted(present))})")
    wildcards = [params for key, params in entries if use_wildcard and key.strip('/') == '**']
    chosen = [params for key, params in entries if key.strip('/') != '**'
              and (wanted is None or key.strip('/') in wanted)]
    if not wildcards and not chosen:
        raise ParameterFileError(f'{parameter_file}: no parameters selected')
    values: dict[str, Any] = {}
    for params in wildcards + chosen:
        _flatten('', params, values)
    return {namespace + name: Parameter(namespace + name, value=value).to_parameter_msg()
            for name, value in values.items()}


def _parameter_entries(path: str) -> list[tuple[str, dict]]:
    """A parameter file's (node key, ros__parameters mapping) pairs, in file order."""
    import yaml
    try:
        with open(path, encoding='utf-8') as stream:
            document = yaml.load(stream, Loader=_merging_loader())  # noqa: S506 - a SafeLoader
    except OSError as exc:
        error = ParameterFileNotFoundError if isinstance(exc, FileNotFoundError) else ParameterFileError
        raise error(f"cannot read parameter file '{path}': {exc.strerror}") from None
    except yaml.YAMLError as exc:
        mark = getattr(exc, 'problem_mark', None)
        where = f':{mark.line + 1}' if mark else ''
        raise ParameterFileError(f"{path}{where}: invalid YAML: {getattr(exc, 'problem', exc)}") from None
    if document is None:
        return []
    if not isinstance(document, dict):
        raise ParameterFileError(f"{path}: expected a mapping of node names at the top level")
    entries = []
    for node_key, params in _node_entries(path, '', document):
        if params is None:
            continue
        if not isinstance(params, dict):
            raise ParameterFileError(f"{path}: 'ros__parameters' of '{node_key}' must be a mapping")
        entries.append((node_key, params))
    return entries


@functools.cache
def _merging_loader() -> type:
    """A yaml SafeLoader under which a key given twice in one mapping merges its mappings,
    as rcl reads parameter files: a file may say `/**:` twice (once with `ros__parameters`,
    once with a node under it) and both count, where plain YAML would keep only the last."""
    import yaml

    def merged(first: dict, second: dict) -> dict:
        out = dict(first)
        for key, value in second.items():
            both = isinstance(out.get(key), dict) and isinstance(value, dict)
            out[key] = merged(out[key], value) if both else value
        return out

    def construct_mapping(loader: yaml.SafeLoader, node: yaml.MappingNode) -> dict:
        loader.flatten_mapping(node)
        mapping: dict = {}
        for key_node, value_node in node.value:
            key = loader.construct_object(key_node, deep=True)
            mapping = merged(mapping, {key: loader.construct_object(value_node, deep=True)})
        return mapping

    class MergingLoader(yaml.SafeLoader):
        pass
    MergingLoader.add_constructor(yaml.resolver.BaseResolver.DEFAULT_MAPPING_TAG, construct_mapping)
    return MergingLoader


def _node_entries(path: str, prefix: str, mapping: dict) -> list[tuple[str, Any]]:
    """(node pattern, ros__parameters) pairs; namespaces may nest (`/ns: node: ros__parameters:`),
    as rcl's parameter files allow."""
    entries = []
    for key, body in mapping.items():
        name = f"{prefix.rstrip('/')}/{str(key).strip('/')}" if prefix else str(key)
        nested = {k: v for k, v in body.items() if k != 'ros__parameters'} if isinstance(body, dict) else None
        if not body or nested is None or any(not isinstance(v, dict) for v in nested.values()):
            raise ParameterFileError(f"{path}: node entry '{name}' has no 'ros__parameters' key")
        if 'ros__parameters' in body:
            entries.append((name, body['ros__parameters']))
        entries += _node_entries(path, name, nested)
    return entries
