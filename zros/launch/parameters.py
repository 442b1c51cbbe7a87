"""Node parameters as a launch file gives them, until they are evaluated into a params file.

Both front ends produce the same `ParamEntry` tree: YAML's `param:` items (`{name, value}`,
nested `param:`, `{from: FILE}`) and Python's `parameters=[{...}, 'file.yaml',
ParameterFile(...), ...]`. Values follow launch_ros's rules: a plain string stays a string, a
value with substitutions is typed by YAML after evaluation (`'1'` -> 1, `'true'` -> True), and
`type:` / `ParameterValue(value_type=...)` forces a type.
"""
from __future__ import annotations

import typing
from pathlib import Path
from typing import Any, NamedTuple

from zros.launch.errors import LaunchFileError, LaunchTypeError, Origin, ParameterTypeError
from zros.launch.origin import origin_here
from zros.launch.template import Substitution, Text, Typed, is_static

__all__ = ['ParamValue', 'TextValue', 'ParamEntry', 'PARAM_TYPES', 'ParameterValue', 'ParameterFile', 'Parameter',
           'param_entries', 'yaml_param_entries']

#: `type:` values of a YAML `param` (launch's type identifiers).
PARAM_TYPES = ('str', 'int', 'float', 'bool', 'list_of_str', 'list_of_int', 'list_of_float',
               'list_of_bool', 'yaml')
_SCALARS = {'str': str, 'int': int, 'float': float, 'bool': bool}
_PYTHON_TYPES = {str: 'str', int: 'int', float: 'float', bool: 'bool'}


def _type_name(value_type: Any, origin: Origin) -> str | None:
    """A ParameterValue's `value_type` (str, int, List[str], ...) as a type identifier."""
    if value_type is None or isinstance(value_type, str):
        if value_type is not None and value_type not in PARAM_TYPES:
            raise LaunchFileError(origin, f"expected a type in {', '.join(PARAM_TYPES)}, got '{value_type}'")
        return value_type
    if value_type in _PYTHON_TYPES:
        return _PYTHON_TYPES[value_type]
    if typing.get_origin(value_type) in (list, typing.List) and typing.get_args(value_type):
        item = typing.get_args(value_type)[0]
        if item in _PYTHON_TYPES:
            return 'list_of_' + _PYTHON_TYPES[item]
    raise LaunchFileError(origin, f'unsupported value_type {value_type!r}: use str, int, float, bool '
                                  'or List[str] (List[int], ...)')


def _is_substitution_list(value: Any) -> bool:
    return isinstance(value, (list, tuple)) and any(isinstance(v, (Substitution, Text)) for v in value) \
        and all(isinstance(v, (str, Substitution, Text)) for v in value)


class TextValue(NamedTuple):
    """A string value: `yaml` when substitutions produced it (launch_ros types those by YAML
    after evaluation) rather than it being written as plain text."""

    text: Text
    yaml: bool


class ParamValue(NamedTuple):
    """One parameter value as written, evaluated by `perform`."""

    value: Any            # a TextValue, a list of TextValues / scalars, or a scalar
    type: str | None      # a PARAM_TYPES identifier, or None for launch's rules
    origin: Origin

    @classmethod
    def of(cls, value: Any, origin: Origin, value_type: Any = None) -> 'ParamValue':
        """A Python value: scalar, list, Substitution (or list of them), ParameterValue."""
        if isinstance(value, ParameterValue):
            return cls.of(value.source, origin, value.value_type)
        type_name = _type_name(value_type, origin)
        if isinstance(value, (Substitution, Text)) or _is_substitution_list(value):
            return cls(TextValue(Text.of(value, origin), True), type_name, origin)
        if isinstance(value, (list, tuple)):
            items = []
            for item in value:
                if isinstance(item, (Substitution, Text)) or _is_substitution_list(item):
                    items.append(TextValue(Text.of(item, origin), True))
                elif isinstance(item, str):
                    items.append(TextValue(Text.of(item, origin), False))
                elif isinstance(item, (int, float, bool)):
                    items.append(item)
                else:
                    raise ParameterTypeError(origin, 'a list parameter holds only strings, numbers, bools '
                                                     f'or substitutions, got {type(item).__name__}')
            return cls(items, type_name, origin)
        if isinstance(value, str):
            return cls(TextValue(Text.of(value, origin), False), type_name, origin)
        if isinstance(value, (int, float, bool, bytes)):
            return cls(value, type_name, origin)
        if value is None:
            raise LaunchFileError(origin, 'a parameter needs a value, got None')
        raise ParameterTypeError(origin, f'unsupported parameter value of type {type(value).__name__}')

    @classmethod
    def from_entity(cls, entity: Any, key: str = 'value') -> 'ParamValue':
        """A YAML `value:` (strings are parsed for substitutions) with the entity's `type:`.
        `type: str` takes the value as written (XML's `value="1.50"` stays '1.50')."""
        from zros.launch.entity import Scalar
        type_name = entity.get_attr('type', optional=True)
        if type_name is not None and type_name not in PARAM_TYPES:
            raise entity.error('type', f"expected one of {', '.join(PARAM_TYPES)}, got '{type_name}'")
        raw = entity.get_attr(key, data_type=Scalar if type_name == 'str' else Any)
        origin = entity.origin_of(key)
        if isinstance(raw, str):
            return cls(cls._yaml_text(raw, origin), type_name, origin)
        if isinstance(raw, list):
            items = []
            for item in raw:
                if isinstance(item, (dict, list)) or item is None:
                    raise LaunchFileError(origin, 'a list parameter holds only strings, numbers or bools')
                items.append(cls._yaml_text(item, origin) if isinstance(item, str) else item)
            return cls(items, type_name, origin)
        if isinstance(raw, dict):
            raise LaunchFileError(origin, "a parameter value cannot be a mapping: use nested 'param:' entries")
        if raw is None:
            raise LaunchFileError(origin, 'a parameter needs a value')
        return cls(raw, type_name, origin)

    @staticmethod
    def _yaml_text(raw: str, origin: Origin) -> TextValue:
        text = Text.parse(raw, origin)
        return TextValue(text, not is_static(text.template))

    def as_given(self) -> Any:
        """The value as launch_ros code sees it before evaluation: text as substitutions."""
        def given(item: Any) -> Any:
            return item.text.substitutions() if isinstance(item, TextValue) else item
        return [given(item) for item in self.value] if isinstance(self.value, list) else given(self.value)

    # -- evaluation --------------------------------------------------------------------------
    def perform(self, context: Any) -> Any:
        if self.type is not None and self.type.startswith('list_of_'):
            return self._as_list(context, _SCALARS[self.type[len('list_of_'):]])
        if isinstance(self.value, list):
            return self._uniform([self._item(item, context, None) for item in self.value], allow_empty=True)
        if self.type in _SCALARS:
            return self._coerce(self._raw(context), _SCALARS[self.type])
        return self._item(self.value, context, None)

    def _raw(self, context: Any) -> Any:
        return self.value.text.perform(context) if isinstance(self.value, TextValue) else self.value

    def _item(self, item: Any, context: Any, data_type: type | None) -> Any:
        from zros.parameter import parse_parameter_value
        if isinstance(item, TextValue):
            text = item.text.perform(context)
            if data_type is not None:
                return self._coerce(text, data_type)
            # launch_ros: plain text stays text; what substitutions produced is typed by YAML
            # (zros keeps text YAML cannot type, a URDF say, as a string: launch_ros refuses it).
            if not (item.yaml and text):
                return text
            value = parse_parameter_value(text)
            return self._uniform(value, allow_empty=False) if isinstance(value, list) else value
        return self._coerce(item, data_type) if data_type is not None else item

    def _uniform(self, values: list, *, allow_empty: bool) -> list:
        """`values` as a ROS array parameter: items of one type (ints among floats become
        floats); an empty list only if written so (one a substitution gives has no type).

        Raises:
            ParameterTypeError: mixed, nested or (from a substitution) empty.
        """
        kinds = {type(v) for v in values}
        if kinds == {int, float}:
            return [float(v) for v in values]
        if (len(kinds) == 1 and kinds <= {bool, int, float, str}) or (allow_empty and not values):
            return values
        raise ParameterTypeError(self.origin, 'Expected a non-empty sequence with items of one type (bool, int, '
                                              f'float or str) for a list parameter, got {values!r}')

    def _as_list(self, context: Any, data_type: type) -> list:
        from zros.parameter import parse_parameter_value
        raw = self.value
        if isinstance(raw, TextValue):
            raw = parse_parameter_value(raw.text.perform(context))
            if not isinstance(raw, list):
                raise LaunchFileError(self.origin, f'expected a list for type {self.type}, got {raw!r}')
            return [self._coerce(item, data_type) for item in raw]
        if not isinstance(raw, list):
            raise LaunchFileError(self.origin, f'expected a list for type {self.type}, got {raw!r}')
        return [self._item(item, context, data_type) for item in raw]

    def _coerce(self, value: Any, data_type: type) -> Any:
        if data_type is str:
            if isinstance(value, bool):
                return 'true' if value else 'false'
            return str(value)
        return Typed(data_type, None, self.origin).convert(value)


# -- launch_ros.parameter_descriptions ----------------------------------------------------------
def _as_given(value: Any) -> Any:
    """launch_ros's view of a value before evaluation: substitutions (or a list with some) as a
    list of substitutions, anything else as given."""
    if isinstance(value, (Substitution, Text)) or _is_substitution_list(value):
        return Text.of(value, origin_here('ParameterValue')).substitutions()
    return value


def _has_substitutions(value: Any) -> bool:
    if isinstance(value, (list, tuple)):
        return any(_has_substitutions(item) for item in value)
    return isinstance(value, (Substitution, Text))


def _check_plain(value: Any, value_type: Any) -> None:
    """A value without substitutions must already be of `value_type` (launch_ros's rule).

    Raises:
        TypeError: it is not (`ParameterValue('1', value_type=int)`).
    """
    if value_type is None or _has_substitutions(value):
        return
    scalar = typing.get_args(value_type)[0] if typing.get_origin(value_type) in (list, typing.List) else None
    if scalar is not None:
        ok = isinstance(value, (list, tuple)) and all(isinstance(v, scalar) for v in value)
    else:
        ok = isinstance(value, value_type) if isinstance(value_type, type) else True
    if not ok:
        raise TypeError(f'value {value!r} is not of value_type {value_type!r}')


class ParameterValue:
    """`ParameterValue(value, value_type=str)`: a value whose type is forced after substitution
    (the robot_description pattern: a `Command` output kept as a string).

    `value` is what was given (substitutions as a list of them) until `evaluate(context)`,
    then the evaluated value, as launch_ros's description keeps it.

    Raises:
        TypeError: a value without substitutions is not of `value_type`.
    """

    def __init__(self, value: Any, *, value_type: Any = None) -> None:
        _check_plain(value, value_type)
        self.source, self.value_type = value, value_type
        self.origin = origin_here('ParameterValue')
        self._evaluated: tuple[Any] | None = None

    @property
    def value(self) -> Any:
        return self._evaluated[0] if self._evaluated is not None else _as_given(self.source)

    def evaluate(self, context: Any) -> Any:
        """The value, typed as a node would get it.

        Raises:
            ValueError: the evaluated text is no value of a ROS parameter (a mixed list).
        """
        try:
            value = ParamValue.of(self.source, self.origin, self.value_type).perform(context)
        except ParameterTypeError as exc:
            raise ValueError(exc.reason) from None
        self._evaluated = (value,)
        return value

    def __repr__(self) -> str:
        return f'ParameterValue({self.source!r}, value_type={self.value_type!r})'


class ParameterFile:
    """`ParameterFile(path, allow_substs=False)`: a ROS 2 parameter file, with substitutions in
    it evaluated when `allow_substs` is true.

    `evaluate(context)` answers the file a node is given: the file itself, or with
    `allow_substs` a temporary copy with the substitutions performed (removed by `cleanup()`);
    `param_file` is that path from then on, as in launch_ros.
    """

    def __init__(self, param_file: Any, *, allow_substs: Any = False) -> None:
        self.source, self.allow_substs = param_file, allow_substs
        self.origin = origin_here('ParameterFile')
        self._evaluated: Path | None = None
        self._temporary = False

    @property
    def param_file(self) -> Any:
        """The evaluated path, or before that the path (a Path as given, text as substitutions)."""
        if self._evaluated is not None:
            return self._evaluated
        return self.source if isinstance(self.source, Path) else Text.of(self.source, self.origin).substitutions()

    def evaluate(self, context: Any) -> Path:
        import tempfile
        from zros.launch.template import parse, perform
        path = Path(Text.of(self.source, self.origin).perform(context))
        allow = (Typed.of(self.allow_substs, bool, self.origin).perform(context)
                 if self.allow_substs is not None else False)
        if allow:
            text = perform(parse(path.read_text(encoding='utf-8')), context)
            with tempfile.NamedTemporaryFile('w', prefix='launch_params_', suffix='.yaml', delete=False) as out:
                out.write(text)
            path, self._temporary = Path(out.name), True
        self._evaluated = path
        return path

    def cleanup(self) -> None:
        """Remove the substituted copy `evaluate` wrote, if any, and go back to the path as
        given (a file used as it is stays evaluated)."""
        if self._temporary and self._evaluated is not None:
            self._evaluated.unlink(missing_ok=True)
            self._evaluated, self._temporary = None, False

    def __repr__(self) -> str:
        return f'ParameterFile({self.source!r}, allow_substs={self.allow_substs!r})'


class Parameter:
    """`Parameter(name, value, value_type=None)`: one parameter, as a `parameters=[...]` item;
    `name` and `value` are as given until `evaluate(context)` returns and keeps them evaluated."""

    def __init__(self, name: Any, value: Any, *, value_type: Any = None) -> None:
        self.source_name, self.value_type = name, value_type
        self.origin = origin_here('Parameter')
        self.parameter_value = ParameterValue(value, value_type=value_type)
        self._name: str | None = None

    @property
    def name(self) -> Any:
        if self._name is not None:
            return self._name
        return Text.of(self.source_name, self.origin).substitutions()

    @property
    def value(self) -> Any:
        return self.parameter_value.value

    def evaluate(self, context: Any) -> tuple[str, Any]:
        self._name = Text.of(self.source_name, self.origin).perform(context)
        return self._name, self.parameter_value.evaluate(context)


# -- entries -----------------------------------------------------------------------------------
class ParamEntry(NamedTuple):
    """One parameter source: `name`+`value`, `name`+nested entries, or a file (`path`)."""

    name: Text | None
    value: ParamValue | None
    nested: tuple['ParamEntry', ...]
    path: Text | None
    allow_substs: Typed | None
    origin: Origin


def yaml_param_entries(entity: Any, parser: Any) -> tuple[ParamEntry, ...]:
    """A YAML `param:` list (nested `param:` lists too)."""
    entries = []
    from zros.launch.entity import Entity
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
                if item.has('type'):
                    raise item.error('type', "'type' and nested 'param' cannot be used together")
                entries.append(ParamEntry(name, None, yaml_param_entries(item, parser), None, None, item.origin))
            elif item.has('value'):
                entries.append(ParamEntry(name, ParamValue.from_entity(item), (), None, None, item.origin))
            else:
                raise item.error(None, f"parameter '{name}' needs a 'value' or nested 'param' entries")
        item.assert_complete()
    return tuple(entries)


def param_entries(parameters: Any, origin: Origin) -> tuple[ParamEntry, ...]:
    """Python `parameters=[...]`: dicts (nested dicts make dotted names), parameter files (a
    path, a substitution or a ParameterFile) and Parameter descriptions, in order."""
    if parameters is None:
        return ()
    if isinstance(parameters, (dict, str, Path, Substitution, ParameterFile)):
        parameters = [parameters]
    entries = []
    for item in parameters:
        if isinstance(item, dict):
            entries.extend(_dict_entries(item, origin))
        elif isinstance(item, ParameterFile):
            allow = Typed.of(item.allow_substs, bool, origin) if item.allow_substs is not None else None
            entries.append(ParamEntry(None, None, (), Text.of(item.source, origin), allow, origin))
        elif isinstance(item, Parameter):
            entries.append(ParamEntry(Text.of(item.source_name, origin), ParamValue.of(item.parameter_value, origin),
                                      (), None, None, origin))
        elif isinstance(item, (str, Path, Substitution, Text)) or _is_substitution_list(item):
            entries.append(ParamEntry(None, None, (), Text.of(item, origin), None, origin))
        else:
            raise LaunchTypeError(origin, 'a parameters item is a dict, a parameter file path or a '
                                          f'ParameterFile, got {type(item).__name__}')
    return tuple(entries)


def _dict_entries(mapping: dict, origin: Origin) -> list[ParamEntry]:
    entries = []
    for key, value in mapping.items():
        if not isinstance(key, (str, Substitution, Text, tuple, list)):
            raise LaunchTypeError(origin, f'a parameter name is a string or substitutions, got {type(key).__name__}')
        name = Text.of(key, origin)
        if isinstance(value, dict):
            entries.append(ParamEntry(name, None, tuple(_dict_entries(value, origin)), None, None, origin))
        else:
            entries.append(ParamEntry(name, ParamValue.of(value, origin), (), None, None, origin))
    return entries

