"""Parser for ROS 2 interface definition text (.msg, .srv, .action).

Interfaces are the source of truth for every message class zros builds: nothing is generated
ahead of time, so this parser must accept everything ROS 2's rosidl accepts in those files and
reject the rest with an error that names the file and line.

The result is plain frozen data (`MessageSpec`, `ServiceSpec`, `ActionSpec`); turning it into
Python classes and codecs is `zros.message`'s job.

The grammar and value rules follow ROS 2's `rosidl_adapter.parser` (what `colcon build` runs on
.msg/.srv/.action files), so a file accepted here builds in ROS 2 and means the same thing.
Where rosidl silently produces a broken value or crashes, this parser is deliberately more
careful or stricter; these are all the differences:

* A `#` inside a quoted string value does not start a comment (rosidl cuts the quoted string
  in half); an unquoted value still ends at the first `#`, string constants included, as in
  rosidl (unlike ROS 1, which kept the whole line of a string constant).
* A line is a constant only if `=` directly follows the name, so `string s a=b` is a field with
  default `a=b` (rosidl mistakes it for a constant and rejects it).
* The `---` separator may carry whitespace and a comment; `pkg/msg/Name` is accepted as a type;
  bare `Header` means `std_msgs/msg/Header` (ROS 1 habit that ROS 2 interfaces rely on).
* Quoted array elements keep their inner spaces and get the same escape handling as scalar
  strings; empty array elements (`[1,,2]`, `["a",]`) are errors; a float32 value that does not
  fit in a float32 is an error; array sizes and string bounds are plain digits.
* The newest rosidl's `@optional` annotation is rejected: the data model has no place for it.
"""
from __future__ import annotations

import codecs
import os
import re
import struct
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from zros.errors import InterfaceParseError

__all__ = [
    'PRIMITIVE_TYPES',
    'FieldType',
    'Field',
    'Constant',
    'MessageSpec',
    'ServiceSpec',
    'ActionSpec',
    'parse_message',
    'parse_service',
    'parse_action',
    'parse_file',
    'strip_comment',
]

#: Primitive type names of ROS 2 IDL.
PRIMITIVE_TYPES = frozenset({
    'bool', 'byte', 'char',
    'float32', 'float64',
    'int8', 'uint8', 'int16', 'uint16', 'int32', 'uint32', 'int64', 'uint64',
    'string', 'wstring',
})


@dataclass(frozen=True)
class FieldType:
    """The type of one field.

    `base` is a primitive name from PRIMITIVE_TYPES or a fully qualified message type
    `pkg/msg/Name` (bare and `pkg/Name` references are resolved at parse time).
    """

    base: str
    string_bound: int | None = None   # N in string<=N / wstring<=N
    array: str | None = None          # None | 'fixed' | 'bounded' | 'unbounded'
    array_size: int | None = None     # N in T[N] / T[<=N]

    @property
    def is_primitive(self) -> bool:
        return self.base in PRIMITIVE_TYPES

    @property
    def is_array(self) -> bool:
        return self.array is not None

    def __str__(self) -> str:
        """The type as written in ROS IDL, e.g. `string<=10`, `float64[36]`, `geometry_msgs/Point[]`."""
        if self.is_primitive:
            text = self.base
        else:
            pkg, _, name = self.base.split('/')
            text = f'{pkg}/{name}'
        if self.string_bound is not None:
            text += f'<={self.string_bound}'
        if self.array == 'fixed':
            text += f'[{self.array_size}]'
        elif self.array == 'bounded':
            text += f'[<={self.array_size}]'
        elif self.array == 'unbounded':
            text += '[]'
        return text


@dataclass(frozen=True)
class Field:
    name: str
    type: FieldType
    default: Any = None       # parsed Python value (list for arrays), None when absent
    has_default: bool = False


@dataclass(frozen=True)
class Constant:
    name: str
    type: str                 # a primitive type name (no arrays in constants)
    value: Any


@dataclass(frozen=True)
class MessageSpec:
    full_name: str            # 'pkg/msg/Name' (or 'pkg/srv/Name_Request', 'pkg/action/Name_Goal', ...)
    fields: tuple[Field, ...]
    constants: tuple[Constant, ...]
    text: str                 # the original text of this message's part of the file
    source: str = '<string>'

    @property
    def package(self) -> str:
        return self.full_name.split('/')[0]

    @property
    def name(self) -> str:
        return self.full_name.split('/')[-1]

    def dependencies(self) -> list[str]:
        """Fully qualified names of the message types this one's fields use."""
        return [f.type.base for f in self.fields if not f.type.is_primitive]


@dataclass(frozen=True)
class ServiceSpec:
    full_name: str            # 'pkg/srv/Name'
    request: MessageSpec      # full_name 'pkg/srv/Name_Request'
    response: MessageSpec     # full_name 'pkg/srv/Name_Response'
    text: str
    source: str = '<string>'


@dataclass(frozen=True)
class ActionSpec:
    full_name: str            # 'pkg/action/Name'
    goal: MessageSpec         # 'pkg/action/Name_Goal'
    result: MessageSpec       # 'pkg/action/Name_Result'
    feedback: MessageSpec     # 'pkg/action/Name_Feedback'
    text: str
    source: str = '<string>'


# --- grammar -------------------------------------------------------------------------------------

#: ROS 1 time types, which rosidl still accepts and maps to their builtin_interfaces messages.
_TYPE_ALIASES = {
    'time': 'builtin_interfaces/msg/Time',
    'duration': 'builtin_interfaces/msg/Duration',
}
_STRING_TYPES = frozenset({'string', 'wstring'})
_FLOAT_TYPES = frozenset({'float32', 'float64'})
#: Inclusive value range of every integer-valued primitive; byte and char are 8-bit unsigned.
_INT_RANGES: dict[str, tuple[int, int]] = {
    'byte': (0, 255),
    'char': (0, 255),
    **{f'int{bits}': (-(1 << (bits - 1)), (1 << (bits - 1)) - 1) for bits in (8, 16, 32, 64)},
    **{f'uint{bits}': (0, (1 << bits) - 1) for bits in (8, 16, 32, 64)},
}
#: rosidl compares the lower-cased text, so `True`, `TRUE` and `true` are all accepted.
_BOOL_WORDS = {'true': True, '1': True, 'false': False, '0': False}
_QUOTES = ('"', "'")
_SEPARATOR = '---'

# Field and package names share rosidl's pattern: no double and no trailing underscore.
_LOWER_NAME_RE = re.compile(r'(?!.*__)(?!.*_$)[a-z][a-z0-9_]*')
_LOWER_NAME_RULE = "[a-z][a-z0-9_]* without '__' or a trailing '_'"
_CONSTANT_NAME_RE = re.compile(r'(?!.*__)(?!.*_$)[A-Z][A-Z0-9_]*')
_CONSTANT_NAME_RULE = "[A-Z][A-Z0-9_]* without '__' or a trailing '_'"
_MESSAGE_NAME_RE = re.compile(r'[A-Z][A-Za-z0-9]*')
_MESSAGE_NAME_RULE = '[A-Z][A-Za-z0-9]*'
_POSITIVE_INT_RE = re.compile(r'[0-9]+')
#: `TYPE NAME` and whatever follows: nothing, a comment, ` DEFAULT` or `=VALUE`.
_HEAD_RE = re.compile(r'(?P<type>[^ #]+)(?: +(?P<name>[^ #=]+))?(?P<tail>.*)')
#: The escapes Python's `unicode_escape` codec understands, which rosidl applies to string
#: values; `bad` catches the truncated ones that would make that codec fail.
_ESCAPE_RE = re.compile(
    r'\\(?:[\\\'"abfnrtv]|[0-7]{1,3}|x[0-9A-Fa-f]{2}|u[0-9A-Fa-f]{4}|U[0-9A-Fa-f]{8}'
    r'|N\{[^}]*\}|(?P<bad>[xuUN]|\Z))')

_KINDS = ('msg', 'srv', 'action')


class _LineError(Exception):
    """What is wrong with one line; the line loop adds `source:line:` to make it public."""


# --- public entry points -------------------------------------------------------------------------

def parse_message(text: str, package: str, name: str, *, source: str = '<string>',
                  kind: str = 'msg') -> MessageSpec:
    """Parse the text of one message; `kind` is the middle part of the full name."""
    _check_interface_name(package, name, source)
    return _parse_part(text, 1, package, f'{package}/{kind}/{name}', source)


def parse_service(text: str, package: str, name: str, *, source: str = '<string>') -> ServiceSpec:
    """Parse a .srv text: request and response separated by one `---` line."""
    _check_interface_name(package, name, source)
    request, response = _split_parts(text, 2, source, 'a service has exactly one')
    prefix = f'{package}/srv/{name}'
    return ServiceSpec(
        full_name=prefix,
        request=_parse_part(request[1], request[0], package, f'{prefix}_Request', source),
        response=_parse_part(response[1], response[0], package, f'{prefix}_Response', source),
        text=text,
        source=source,
    )


def service_event_spec(service: ServiceSpec) -> MessageSpec:
    """The `pkg/srv/Name_Event` message that service introspection publishes for a service:
    what happened (service_msgs/ServiceEventInfo) and, when contents are introspected, the
    request or the response (rosidl generates it beside Request and Response)."""
    full_name = f'{service.full_name}_Event'
    fields = (
        Field('info', FieldType('service_msgs/msg/ServiceEventInfo')),
        Field('request', FieldType(service.request.full_name, array='bounded', array_size=1)),
        Field('response', FieldType(service.response.full_name, array='bounded', array_size=1)),
    )
    text = '\n'.join(f'{field.type} {field.name}' for field in fields) + '\n'
    return MessageSpec(full_name=full_name, fields=fields, constants=(), text=text, source=service.source)


def parse_action(text: str, package: str, name: str, *, source: str = '<string>') -> ActionSpec:
    """Parse an .action text: goal, result and feedback separated by two `---` lines."""
    _check_interface_name(package, name, source)
    goal, result, feedback = _split_parts(text, 3, source, 'an action has exactly two')
    prefix = f'{package}/action/{name}'
    return ActionSpec(
        full_name=prefix,
        goal=_parse_part(goal[1], goal[0], package, f'{prefix}_Goal', source),
        result=_parse_part(result[1], result[0], package, f'{prefix}_Result', source),
        feedback=_parse_part(feedback[1], feedback[0], package, f'{prefix}_Feedback', source),
        text=text,
        source=source,
    )


def parse_file(path: str | os.PathLike[str]) -> MessageSpec | ServiceSpec | ActionSpec:
    """Parse `<package>/<kind>/<Name>.<kind>`, the layout of every ROS 2 interface package.

    Package, kind and name come from the path because that is where ROS 2 takes them from;
    a file that cannot be read is reported like a syntax error, so callers handle one error type.
    """
    source = os.fspath(path)
    file = Path(source).absolute()
    kind = file.parent.name
    if kind not in _KINDS or file.suffix != f'.{kind}':
        raise InterfaceParseError(
            f"{source}:1: cannot tell the interface kind: expected a path like "
            f"<package>/msg/<Name>.msg, <package>/srv/<Name>.srv or <package>/action/<Name>.action")
    try:
        data = file.read_bytes()
    except OSError as err:
        raise InterfaceParseError(f'{source}:1: cannot read file: {err.strerror or err}') from err
    try:
        text = data.decode('utf-8')
    except UnicodeDecodeError as err:
        line = data.count(b'\n', 0, err.start) + 1
        raise InterfaceParseError(
            f'{source}:{line}: not valid UTF-8 (byte 0x{data[err.start]:02x})') from err
    parser = {'msg': parse_message, 'srv': parse_service, 'action': parse_action}[kind]
    return parser(text, file.parent.parent.name, file.stem, source=source)


# --- files and parts -----------------------------------------------------------------------------

def _check_interface_name(package: str, name: str, source: str) -> None:
    """Reject names that would give the interface a full name no ROS 2 tool can address."""
    if not _LOWER_NAME_RE.fullmatch(package):
        raise InterfaceParseError(
            f"{source}:1: invalid package name '{package}': must match {_LOWER_NAME_RULE}")
    if not _MESSAGE_NAME_RE.fullmatch(name):
        raise InterfaceParseError(
            f"{source}:1: invalid interface name '{name}': must match {_MESSAGE_NAME_RULE}")


def _split_parts(text: str, count: int, source: str, rule: str) -> list[tuple[int, str]]:
    """Cut a .srv/.action text at its `---` lines into (first line number, original text) parts.

    Each part keeps its exact original text, and its line number, so that errors in the response
    or feedback still point at the right line of the file.
    """
    lines = text.splitlines(keepends=True)
    separators = [index for index, line in enumerate(lines) if _is_separator(line)]
    if len(separators) >= count:
        extra = separators[count - 1]
        raise InterfaceParseError(
            f"{source}:{extra + 1}: unexpected '{_SEPARATOR}' separator: "
            f"{rule} '{_SEPARATOR}' line")
    if len(separators) < count - 1:
        raise InterfaceParseError(
            f"{source}:{max(len(lines), 1)}: found {len(separators)} '{_SEPARATOR}' separator "
            f"line(s) but {rule} '{_SEPARATOR}' line")
    bounds = [-1, *separators, len(lines)]
    return [(start + 2, ''.join(lines[start + 1:end])) for start, end in zip(bounds, bounds[1:])]


def _is_separator(line: str) -> bool:
    """A `---` line, allowing surrounding whitespace and a trailing comment."""
    return line.partition('#')[0].strip() == _SEPARATOR


def _parse_part(text: str, first_line: int, package: str, full_name: str,
                source: str) -> MessageSpec:
    """Parse the lines of one message; `first_line` is the file line number of its first line."""
    fields: list[Field] = []
    constants: list[Constant] = []
    seen: dict[str, int] = {}  # field and constant names cannot clash: their cases differ
    for lineno, line in enumerate(text.splitlines(), start=first_line):
        try:
            item = _parse_line(line, package)
        except _LineError as err:
            raise InterfaceParseError(f'{source}:{lineno}: {err}') from None
        if item is None:
            continue
        what = 'field' if isinstance(item, Field) else 'constant'
        if item.name in seen:
            raise InterfaceParseError(
                f"{source}:{lineno}: duplicate {what} name '{item.name}' "
                f"(first defined on line {seen[item.name]})")
        seen[item.name] = lineno
        (fields if isinstance(item, Field) else constants).append(item)
    return MessageSpec(full_name=full_name, fields=tuple(fields), constants=tuple(constants),
                       text=text, source=source)


# --- lines ---------------------------------------------------------------------------------------

def _parse_line(line: str, package: str) -> Field | Constant | None:
    """Parse one line into a field or constant, or None for blank and comment lines."""
    line = line.replace('\t', ' ').rstrip()  # rosidl treats tabs as spaces everywhere
    content = line.lstrip()
    if not content or content.startswith('#'):
        return None
    if line[0].isspace():
        # rosidl fails on indented definitions (only comments may be indented)
        raise _LineError(f"unexpected indentation before '{content}'")
    if _is_separator(line):
        raise _LineError(f"unexpected '{_SEPARATOR}' separator: "
                         f"only .srv and .action files have parts")
    if line.startswith('@'):
        raise _LineError(f"annotation '{line.split()[0]}' is not supported")
    head = _HEAD_RE.fullmatch(line)
    assert head is not None  # the pattern matches any line that starts with a non-space non-'#'
    type_token, name = head['type'], head['name']
    if name is None:
        raise _LineError(f"missing name after type '{type_token}' "
                         f"(expected 'TYPE NAME [DEFAULT]' or 'TYPE NAME=VALUE')")
    field_type = _parse_type(type_token, package)
    rest = head['tail'].lstrip(' ')
    if rest.startswith('='):
        return _make_constant(type_token, field_type, name, strip_comment(rest[1:].lstrip()))
    return _make_field(field_type, name, strip_comment(rest))


def strip_comment(value: str) -> str:
    """Cut a value at its comment, without cutting inside a quoted string or array element.

    A quote only opens a string at the start of the value or of an array element, so the
    apostrophe in an unquoted `don't` is text. An unterminated quote falls back to rosidl's rule:
    the first `#` starts the comment.
    """
    item_start = True
    index = 0
    while index < len(value):
        char = value[index]
        if char == '#':
            return value[:index].rstrip()
        if item_start and char in _QUOTES:
            end = _closing_quote(value, index)
            if end < 0:
                return (value[:index] + value[index:].partition('#')[0]).rstrip()
            index = end + 1
            item_start = False
            continue
        if char in '[,':
            item_start = True
        elif char != ' ':
            item_start = False
        index += 1
    return value.rstrip()


def _closing_quote(text: str, start: int) -> int:
    """Index of the unescaped quote closing the one at `start`, or -1 if there is none."""
    quote = text[start]
    index = start + 1
    while index < len(text):
        if text[index] == '\\':
            index += 2
        elif text[index] == quote:
            return index
        else:
            index += 1
    return -1


def _make_field(field_type: FieldType, name: str, default_text: str) -> Field:
    """Build a field; an empty `default_text` means none, since rosidl has no empty default."""
    if not _LOWER_NAME_RE.fullmatch(name):
        raise _LineError(f"invalid field name '{name}': must match {_LOWER_NAME_RULE}")
    if not default_text:
        return Field(name, field_type)
    try:
        default = _parse_default(field_type, default_text)
    except _LineError as err:
        raise _LineError(f"invalid default value for field '{name}': {err}") from None
    return Field(name, field_type, default, has_default=True)


def _make_constant(type_token: str, field_type: FieldType, name: str, value_text: str) -> Constant:
    """Build a constant; only a string constant may be empty (rosidl allows `string S=`)."""
    if not _CONSTANT_NAME_RE.fullmatch(name):
        raise _LineError(f"invalid constant name '{name}': must match {_CONSTANT_NAME_RULE}")
    if not field_type.is_primitive or field_type != FieldType(field_type.base):
        raise _LineError(f"constant '{name}' must have a primitive non-array type, "
                         f"not '{type_token}'")
    if not value_text and field_type.base not in _STRING_TYPES:
        raise _LineError(f"missing value for constant '{name}'")
    try:
        value = _parse_scalar(field_type.base, None, value_text)
    except _LineError as err:
        raise _LineError(f"invalid value for constant '{name}': {err}") from None
    return Constant(name, field_type.base, value)


# --- types ---------------------------------------------------------------------------------------

def _parse_type(token: str, package: str) -> FieldType:
    """Parse `BASE[<=N][ARRAY]`, resolving message references to `pkg/msg/Name`."""
    array = size = None
    base = token
    if token.endswith(']'):
        open_index = token.rfind('[')
        if open_index < 0:
            raise _LineError(f"invalid type '{token}': ']' without '['")
        base, spec = token[:open_index], token[open_index + 1:-1]
        if not spec:
            array = 'unbounded'
        else:
            array = 'bounded' if spec.startswith('<=') else 'fixed'
            size = _positive_int(spec.removeprefix('<='),
                                 f"array size in '{token}' must be an integer > 0, "
                                 f"optionally prefixed with '<='")
    if not base or '[' in base or ']' in base:
        raise _LineError(f"invalid type '{token}'")
    resolved, string_bound = _parse_base_type(base, token, package)
    return FieldType(resolved, string_bound, array, size)


def _parse_base_type(base: str, token: str, package: str) -> tuple[str, int | None]:
    """Resolve the element type of `token` to (primitive or `pkg/msg/Name`, string bound)."""
    if base in PRIMITIVE_TYPES:
        return base, None
    if base in _TYPE_ALIASES:
        return _TYPE_ALIASES[base], None
    prefix, bounded, bound = base.partition('<=')
    if bounded:
        if prefix not in _STRING_TYPES:
            raise _LineError(f"invalid type '{token}': only string and wstring take an upper "
                             f"bound '<=N'")
        return prefix, _positive_int(bound, f"string bound in '{token}' must be an integer > 0")
    parts = base.split('/')
    if len(parts) == 1:
        if not base[0].isupper():
            raise _LineError(f"unknown primitive type '{base}'")
        # bare Header is std_msgs' by a convention ROS 1 started and ROS 2 messages still use
        parts = ['std_msgs' if base == 'Header' else package, base]
    elif len(parts) == 3 and parts[1] == 'msg':
        parts = [parts[0], parts[2]]
    elif len(parts) != 2:
        raise _LineError(f"invalid type '{token}': expected a primitive type, 'Name', "
                         f"'pkg/Name' or 'pkg/msg/Name'")
    type_package, name = parts
    if not _LOWER_NAME_RE.fullmatch(type_package):
        raise _LineError(f"invalid package name '{type_package}' in type '{token}': "
                         f"must match {_LOWER_NAME_RULE}")
    if not _MESSAGE_NAME_RE.fullmatch(name):
        raise _LineError(f"invalid message name '{name}' in type '{token}': "
                         f"must match {_MESSAGE_NAME_RULE}")
    return f'{type_package}/msg/{name}', None


def _positive_int(text: str, problem: str) -> int:
    """Parse a size or bound; plain digits only, so `+3` or `3_0` are not taken as sizes."""
    if not _POSITIVE_INT_RE.fullmatch(text) or int(text) == 0:
        raise _LineError(f"{problem}, not '{text}'")
    return int(text)


# --- values --------------------------------------------------------------------------------------

def _parse_default(field_type: FieldType, text: str) -> Any:
    """Parse a field default: a scalar, or a `[...]` list checked against the array size."""
    if not field_type.is_primitive:
        raise _LineError(f"'{text}' given, but only primitive fields take a default and "
                         f"'{field_type}' is a message type")
    if not field_type.is_array:
        return _parse_scalar(field_type.base, field_type.string_bound, text)
    items = _split_array(text)
    size = field_type.array_size
    if field_type.array == 'fixed' and len(items) != size:
        raise _LineError(f"'{text}' has {len(items)} element(s), "
                         f"'{field_type}' needs exactly {size}")
    if field_type.array == 'bounded' and len(items) > size:
        raise _LineError(f"'{text}' has {len(items)} elements, "
                         f"more than the {size} '{field_type}' allows")
    values = []
    for index, item in enumerate(items):
        try:
            values.append(_parse_scalar(field_type.base, field_type.string_bound, item))
        except _LineError as err:
            raise _LineError(f'element {index} of {text}: {err}') from None
    return values


def _split_array(text: str) -> list[str]:
    """Split `[a, b, ...]` into element texts; a quoted element may contain commas."""
    if not (text.startswith('[') and text.endswith(']')):
        raise _LineError(f"array value '{text}' must be enclosed in '[' and ']'")
    inner = text[1:-1]
    if not inner.strip():
        return []
    items = []
    index = 0
    while True:
        while index < len(inner) and inner[index] == ' ':
            index += 1
        if index < len(inner) and inner[index] in _QUOTES:
            end = _closing_quote(inner, index)
            if end < 0:
                raise _LineError(f"unterminated quoted element in '{text}'")
            item = inner[index:end + 1]
            index = end + 1
            while index < len(inner) and inner[index] == ' ':
                index += 1
            if index < len(inner) and inner[index] != ',':
                raise _LineError(f"unexpected text after {item} in '{text}'")
        else:
            comma = inner.find(',', index)
            comma = len(inner) if comma < 0 else comma
            item = inner[index:comma].strip()
            index = comma
            if not item:
                raise _LineError(f"empty element in array value '{text}'")
        items.append(item)
        if index >= len(inner):
            return items
        index += 1  # past the comma


def _parse_scalar(base: str, string_bound: int | None, text: str) -> Any:
    """Parse one primitive value the way rosidl does, as the Python value zros stores."""
    if base == 'bool':
        try:
            return _BOOL_WORDS[text.lower()]
        except KeyError:
            raise _LineError(f"'{text}' is not a bool (use true, false, 1 or 0)") from None
    if base in _INT_RANGES:
        return _parse_int(base, text)
    if base in _FLOAT_TYPES:
        return _parse_float(base, text)
    return _parse_string(text, string_bound)


def _parse_int(base: str, text: str) -> int:
    """Decimal first, then Python literal syntax (`0x1F`, `0b101`), as rosidl tries them."""
    try:
        value = int(text)
    except ValueError:
        try:
            value = int(text, 0)
        except ValueError:
            raise _LineError(f"'{text}' is not an integer") from None
    low, high = _INT_RANGES[base]
    if not low <= value <= high:
        raise _LineError(f"'{text}' is out of range for {base} ({low}..{high})")
    return value


def _parse_float(base: str, text: str) -> float:
    """Python float syntax (so also `inf` and `nan`), as rosidl; float32 must fit in 32 bits."""
    try:
        value = float(text)
    except ValueError:
        raise _LineError(f"'{text}' is not a floating point number") from None
    if base == 'float32':
        try:
            struct.pack('<f', value)
        except OverflowError:
            raise _LineError(f"'{text}' is out of range for float32") from None
    return value


def _parse_string(text: str, string_bound: int | None) -> str:
    """Unquote (when the whole value is quoted) and decode escapes, then check the bound.

    Like rosidl, unquoted text is taken as is apart from escapes, and inside quotes the quote
    character itself must be escaped. rosidl decodes escapes with Python's `unicode_escape`
    when it writes the value into the generated .idl, so `\\n` means a newline here too.
    """
    if len(text) >= 2 and text[0] in _QUOTES and text[-1] == text[0]:
        end = _closing_quote(text, 0)
        if end < 0:
            raise _LineError(f'unterminated quoted string {text}')
        if end != len(text) - 1:
            raise _LineError(f'unescaped {text[0]} inside quoted string {text}')
        value = _decode_escapes(text[1:-1], text)
    else:
        value = _decode_escapes(text, text)
    if string_bound is not None and len(value) > string_bound:
        raise _LineError(f'string {text} is {len(value)} characters long, '
                         f'more than the bound {string_bound}')
    return value


def _decode_escapes(value: str, text: str) -> str:
    """Decode backslash escapes; unknown ones (`\\d`) stay as written, like Python's codec."""
    def decode(match: re.Match[str]) -> str:
        try:
            if match['bad'] is None:
                return codecs.decode(match[0], 'unicode_escape')
        except UnicodeDecodeError:
            pass
        raise _LineError(f"invalid escape sequence '{match[0]}' in {text}")
    return _ESCAPE_RE.sub(decode, value)
