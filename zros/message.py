"""Message classes built from parsed interface specs, and their MessagePack codec.

Classes are made at import time from the IDL text (no build step). Each field is a property
over a slot, as in rclpy's generated code: assignment checks the value's type and range and
fails with an error that names the message and the field, so a bad value is caught where the
user wrote it rather than deep inside a publish.

Field values are what rclpy gives (rosidl_generator_py): numeric sequences (`float32[]`,
`uint8[]`, `int32[<=5]`, ...) are `array.array`, fixed-size numeric arrays (`float64[36]`) are
numpy arrays, `byte` is a 1-byte `bytes` and `byte[]` a list of them, other arrays are lists.
Assignment converts lists, tuples, numpy arrays and array.arrays to that form.

Wire format, protocol v2 (docs/protocol.md): a message is one MessagePack array of its field
values in definition order (nested messages are nested arrays) followed by the *tail*: the raw
little-endian bytes of its numeric arrays, in the order the header lists them; the header holds
each numeric array's element count. So a large array is copied once into the payload when
sent and once out of it when received, never through msgpack. The encoder and the strict
decoder of each type are Python source generated and compiled once per type: the decoder checks
every value as assignment would (types, ranges, string bounds, array lengths), so a malformed
payload raises DecodeError and never becomes a message.
"""
from __future__ import annotations

import array
import hashlib
import math
import operator
import sys
import threading
from typing import Any, Callable, Protocol, TypeVar

import msgpack
import numpy as np

from zros.errors import DecodeError, MessageTypeError
from zros.fixed_layout import fixed_decoder, fixed_encoder, layout
from zros.idl import ActionSpec, Field, FieldType, MessageSpec, ServiceSpec

__all__ = ['Message', 'make_message_class', 'make_service_class', 'make_action_class', 'type_hash',
           'ARRAY_TYPECODES', 'NUMPY_DTYPES', 'serialize', 'serialize_parts', 'packed_array', 'deserialize',
           'encoder', 'decoder', 'MsgT', 'SrvRequestT', 'SrvResponseT', 'Srv', 'register_stand_in']

# Type variables for the typed entities (rclpy's type_support has the same): with them a checker
# or an editor knows that `create_publisher(String, ...)` returns a `Publisher[String]` whose
# `publish` takes a `String`. Interface classes are built at run time, so a checker sees them as
# Any unless the user's code declares stand-ins; either way the annotations cost nothing at run time.
MsgT = TypeVar('MsgT')
SrvRequestT = TypeVar('SrvRequestT')
SrvResponseT = TypeVar('SrvResponseT')


_RequestT_co = TypeVar('_RequestT_co', covariant=True)
_ResponseT_co = TypeVar('_ResponseT_co', covariant=True)


class Srv(Protocol[_RequestT_co, _ResponseT_co]):
    """What a checker knows of a service class: its Request and Response classes (read-only,
    so that a class with nested `Request` and `Response` classes matches)."""

    @property
    def Request(self) -> type[_RequestT_co]: ...  # noqa: N802 - the generated classes' names

    @property
    def Response(self) -> type[_ResponseT_co]: ...  # noqa: N802

#: array.array typecode of each numeric primitive, as rclpy uses them (`char` is uint8 in ROS 2).
ARRAY_TYPECODES: dict[str, str] = {
    'int8': 'b', 'uint8': 'B', 'char': 'B', 'int16': 'h', 'uint16': 'H', 'int32': 'i',
    'uint32': 'I', 'int64': 'q', 'uint64': 'Q', 'float32': 'f', 'float64': 'd',
}
#: numpy dtype of each numeric primitive as it travels in the tail (little-endian).
NUMPY_DTYPES: dict[str, np.dtype] = {
    base: np.dtype(code).newbyteorder('<') for base, code in ARRAY_TYPECODES.items()}
_NATIVE_DTYPES = {base: np.dtype(code) for base, code in ARRAY_TYPECODES.items()}
assert all(array.array(code).itemsize == NUMPY_DTYPES[base].itemsize for base, code in ARRAY_TYPECODES.items())
_SWAP = sys.byteorder == 'big'  # the tail is little-endian; a big-endian host swaps on the way

_INT_RANGES = {
    'byte': (0, 255), 'char': (0, 255),
    'int8': (-2**7, 2**7 - 1), 'uint8': (0, 2**8 - 1),
    'int16': (-2**15, 2**15 - 1), 'uint16': (0, 2**16 - 1),
    'int32': (-2**31, 2**31 - 1), 'uint32': (0, 2**32 - 1),
    'int64': (-2**63, 2**63 - 1), 'uint64': (0, 2**64 - 1),
}
_FLOAT32_MAX = 3.4028234663852886e38
_ONE_BYTE = tuple(bytes([i]) for i in range(256))  # the `bytes` value of each byte, shared


def _kind(ftype: FieldType, nested: type | None) -> str:
    """How a field is held and sent: 'scalar', 'nested', 'sequence' (array.array of numbers),
    'fixed' (numpy array of numbers), 'bytes' (list of 1-byte bytes), 'list' (anything else)."""
    if not ftype.is_array:
        return 'nested' if nested is not None else 'scalar'
    if ftype.base in ARRAY_TYPECODES:
        return 'fixed' if ftype.array == 'fixed' else 'sequence'
    return 'bytes' if ftype.base == 'byte' else 'list'


class Message:
    """Base of every generated message class.

    Generated subclasses set `_TYPE` ('pkg/msg/Name'), `_FIELDS` (names in definition order),
    `_FIELD_TYPES` (IDL type text per field), `_HASH`, `_HAS_TAIL` and the codec functions:
    `_ENC(m, tail)` returns the header value and appends numeric arrays to `tail`;
    `_DEC(header, buffer, offset)` returns (message, offset after its arrays), and a type
    without numeric arrays also has `_DEC1(header)`, which returns the message. `_LAYOUT` is
    the type's fixed MessagePack layout (zros.fixed_layout) when it is a tree of float64 fields.
    """

    __slots__ = ()
    _TYPE: str = ''
    _FIELDS: tuple[str, ...] = ()
    _FIELD_TYPES: dict[str, str] = {}
    _HASH: str = ''
    _HAS_TAIL = False
    _LAYOUT: tuple | None = None
    _SPEC: MessageSpec
    _DEFAULTS: tuple[tuple[str, Callable[[], Any]], ...] = ()
    _ENC: Callable[[Any, list], Any]
    _DEC: Callable[[Any, memoryview, int], tuple[Any, int]]

    def __init__(self, **kwargs: Any) -> None:
        if kwargs:
            unknown = [k for k in kwargs if k not in self._FIELD_TYPES]
            if unknown:
                raise MessageTypeError(
                    f"{self._TYPE} has no field(s) {', '.join(map(repr, unknown))}; "
                    f"fields are: {', '.join(self._FIELDS) or '(none)'}")
        for name, make_default in self._DEFAULTS:
            if name in kwargs:
                setattr(self, name, kwargs[name])
            else:
                object.__setattr__(self, '_' + name, make_default())

    @classmethod
    def get_fields_and_field_types(cls) -> dict[str, str]:
        """rclpy's introspection entry point: field name -> IDL type text."""
        return dict(cls._FIELD_TYPES)

    def __eq__(self, other: object) -> bool:
        if type(other) is not type(self):
            return NotImplemented
        for name in self._FIELDS:
            a, b = getattr(self, '_' + name), getattr(other, '_' + name)
            if isinstance(a, np.ndarray):
                if not np.array_equal(a, b):
                    return False
            elif a != b:
                return False
        return True

    __hash__ = None  # mutable, like rclpy messages

    def __repr__(self) -> str:
        """rclpy's form: `pkg.msg.Name(field=value, ...)`, numeric sequences shown as lists."""
        dotted = self._TYPE.replace('/', '.')
        parts = []
        for name in self._FIELDS:
            value = getattr(self, '_' + name)
            text = repr(value.tolist()) if type(value) is array.array else repr(value)
            parts.append(f'{name}={text}')
        return f"{dotted}({', '.join(parts)})"

    def __copy__(self) -> 'Message':
        return deserialize(serialize(self), type(self))

    def __deepcopy__(self, memo: dict) -> 'Message':
        return deserialize(serialize(self), type(self))


# -- stand-ins: objects a message field converts on assignment -----------------------------------
#: message type -> {class: conversion}. rclpy code fills messages with its own objects where a
#: message is expected (`ParameterEvent(new_parameters=[Parameter(...)])`: rclpy's generated
#: classes do not check fields by default); such a value is converted when it is assigned.
_STAND_INS: dict[str, dict[type, Callable[[Any], Any]]] = {}


def register_stand_in(message_type: str, cls: type, to_message: Callable[[Any], Any]) -> None:
    """Let a field of `message_type` ('pkg/msg/Name') take instances of `cls`, converted with
    `to_message` as they are assigned (in a list too). A list changed in place afterwards is
    checked strictly when the message is serialized: the conversion runs on assignment only.
    """
    _STAND_INS.setdefault(message_type, {})[cls] = to_message


# -- checks shared by assignment and decoding --------------------------------------------------
def _type_error(msg_type: str, field: str, expected: str, value: Any) -> MessageTypeError:
    return MessageTypeError(
        f"{msg_type}.{field} must be {expected}, got {type(value).__name__} {value!r:.60}")


def _scalar_checker(msg_type: str, name: str, ftype: FieldType,
                    nested: type | None, stand_ins: bool = True) -> Callable[[Any], Any]:
    """Return a function that validates one scalar value of this field and returns it in the
    form the message holds (an int for a float field becomes a float, a registered stand-in its
    message, and so on; `stand_ins=False` refuses those, for what is checked before encoding)."""
    base = ftype.base
    if nested is not None:
        expected = nested._TYPE
        conversions = _STAND_INS.setdefault(expected, {}) if stand_ins else {}

        def check_nested(value: Any) -> Any:
            if type(value) is not nested:
                convert = conversions.get(type(value))
                if convert is None:
                    raise _type_error(msg_type, name, f'a {expected} message', value)
                return convert(value)
            return value
        return check_nested
    if base == 'bool':
        def check_bool(value: Any) -> bool:
            if isinstance(value, (bool, np.bool_)):
                return bool(value)
            raise _type_error(msg_type, name, 'a bool', value)
        return check_bool
    if base in ('float32', 'float64'):
        limit = _FLOAT32_MAX if base == 'float32' else None

        def check_float(value: Any) -> float:
            if isinstance(value, (float, int, np.floating, np.integer)) and not isinstance(value, (bool, np.bool_)):
                value = float(value)
                if limit is not None and not math.isinf(value) and abs(value) > limit:
                    raise MessageTypeError(f'{msg_type}.{name} = {value!r} is out of range for float32')
                return value
            raise _type_error(msg_type, name, f'a float ({base})', value)
        return check_float
    if base == 'byte':
        def check_byte(value: Any) -> bytes:
            """rclpy's `byte` is a bytes of length 1; an int 0-255 is taken as that byte."""
            if isinstance(value, (bytes, bytearray)) and len(value) == 1:
                return _ONE_BYTE[value[0]]
            if isinstance(value, (int, np.integer)) and not isinstance(value, (bool, np.bool_)):
                if 0 <= value <= 255:
                    return _ONE_BYTE[value]
                raise MessageTypeError(f'{msg_type}.{name} = {value} is out of range for byte [0, 255]')
            raise _type_error(msg_type, name, 'a bytes of length 1 (byte)', value)
        return check_byte
    if base in _INT_RANGES:
        low, high = _INT_RANGES[base]
        text_ok = base == 'char'

        def check_int(value: Any) -> int:
            if text_ok and isinstance(value, str) and len(value) == 1:
                value = ord(value)
            if isinstance(value, (int, np.integer)) and not isinstance(value, (bool, np.bool_)):
                value = int(value)
                if low <= value <= high:
                    return value
                raise MessageTypeError(
                    f'{msg_type}.{name} = {value} is out of range for {base} [{low}, {high}]')
            raise _type_error(msg_type, name, f'an int ({base})', value)
        return check_int
    if base in ('string', 'wstring'):
        bound = ftype.string_bound

        def check_str(value: Any) -> str:
            if not isinstance(value, str):
                raise _type_error(msg_type, name, f'a str ({base})', value)
            if bound is not None and len(value) > bound:
                raise MessageTypeError(
                    f'{msg_type}.{name} is longer than its bound of {bound} characters')
            return value
        return check_str
    raise AssertionError(f'unhandled type {base}')  # the parser only yields the types above


def _length_checker(msg_type: str, name: str, ftype: FieldType) -> Callable[[int], None]:
    size = ftype.array_size

    def check_length(length: int) -> None:
        if ftype.array == 'fixed' and length != size:
            raise MessageTypeError(f'{msg_type}.{name} must have exactly {size} elements, got {length}')
        if ftype.array == 'bounded' and length > size:
            raise MessageTypeError(f'{msg_type}.{name} may have at most {size} elements, got {length}')
    return check_length


def _numbers(msg_type: str, name: str, ftype: FieldType, value: Any) -> np.ndarray:
    """`value` (any sequence of numbers) as a 1-D numpy array of the field's type, after the
    checks a scalar of that type gets: ints for integer fields, in range, float32 range."""
    base = ftype.base
    dtype = _NATIVE_DTYPES[base]
    expected = f'a sequence of {base}'
    if isinstance(value, (str, dict)) or not hasattr(value, '__iter__'):
        raise _type_error(msg_type, name, expected, value)
    if isinstance(value, (bytes, bytearray, memoryview)) and dtype.itemsize == 1:
        if dtype.kind == 'u':
            return np.frombuffer(value, np.uint8)  # every byte is a valid uint8 (UUIDs, pixels)
        probe = np.frombuffer(value, np.uint8)
    else:
        try:
            probe = np.asarray(value if hasattr(value, '__len__') else list(value))
        except (ValueError, TypeError, OverflowError) as exc:
            raise MessageTypeError(f'{msg_type}.{name} must be {expected}: {exc}') from None
    if probe.ndim != 1:
        if probe.size == 0:
            probe = probe.reshape(0)
        else:
            raise MessageTypeError(f'{msg_type}.{name} must be one-dimensional, got shape {probe.shape}')
    if probe.size == 0:
        return np.zeros(0, dtype)
    kind = probe.dtype.kind
    if dtype.kind in 'iu':
        info = np.iinfo(dtype)
        if kind in 'fO' and isinstance(value, (list, tuple)) and all(
                isinstance(v, (int, np.integer)) and not isinstance(v, (bool, np.bool_)) for v in value):
            # Python ints that no one numpy int type holds together ([0, 2**63]) became floats or objects
            if min(value) < info.min or max(value) > info.max:
                raise MessageTypeError(f'{msg_type}.{name} has values out of range for {base}')
            return np.array(value, dtype=dtype)
        if kind not in 'iu':
            raise _type_error(msg_type, name, f'{expected} (ints)', value)
        if probe.min() < info.min or probe.max() > info.max:
            raise MessageTypeError(f'{msg_type}.{name} has values out of range for {base}')
    else:
        if kind not in 'iuf':
            raise _type_error(msg_type, name, f'{expected} (numbers)', value)
        if base == 'float32' and kind == 'f':
            finite = probe[np.isfinite(probe)]
            if finite.size and np.abs(finite).max() > _FLOAT32_MAX:
                raise MessageTypeError(f'{msg_type}.{name} has values out of range for float32')
    return np.ascontiguousarray(probe, dtype=dtype)


def _sequence_setter(msg_type: str, field: Field) -> Callable[[Any, Any], None]:
    """A numeric sequence is an array.array with rclpy's typecode; one of that typecode is kept
    as given (as rclpy does), anything else is converted after the element checks."""
    name, ftype, slot = field.name, field.type, '_' + field.name
    code = ARRAY_TYPECODES[ftype.base]
    check_length = _length_checker(msg_type, name, ftype)
    set_slot, new_array = object.__setattr__, array.array

    def set_sequence(self: Any, value: Any) -> None:
        if type(value) is not new_array or value.typecode != code:
            numbers = _numbers(msg_type, name, ftype, value)
            value = new_array(code)
            value.frombytes(memoryview(numbers).cast('B'))
        check_length(len(value))
        set_slot(self, slot, value)
    return set_sequence


def _fixed_setter(msg_type: str, field: Field) -> Callable[[Any, Any], None]:
    """A fixed-size numeric array is a numpy array of the field's dtype (as rclpy)."""
    name, ftype, slot = field.name, field.type, '_' + field.name
    dtype, shape = _NATIVE_DTYPES[ftype.base], (ftype.array_size,)
    check_length = _length_checker(msg_type, name, ftype)
    set_slot = object.__setattr__

    def set_fixed(self: Any, value: Any) -> None:
        if not (type(value) is np.ndarray and value.dtype == dtype and value.shape == shape):
            value = _numbers(msg_type, name, ftype, value)
            check_length(len(value))
            if not value.flags.writeable or value.base is not None:
                value = value.copy()
        set_slot(self, slot, value)
    return set_fixed


def _make_setter(msg_type: str, field: Field, nested: type | None) -> Callable[[Any, Any], None]:
    kind = _kind(field.type, nested)
    if kind == 'sequence':
        return _sequence_setter(msg_type, field)
    if kind == 'fixed':
        return _fixed_setter(msg_type, field)
    name, ftype, slot = field.name, field.type, '_' + field.name
    set_slot = object.__setattr__
    check = _scalar_checker(msg_type, name, ftype, nested)
    if kind in ('list', 'bytes'):
        check_length = _length_checker(msg_type, name, ftype)

        def set_list(self: Any, value: Any) -> None:
            if kind == 'bytes' and isinstance(value, (bytes, bytearray)):
                items = [_ONE_BYTE[b] for b in value]  # rclpy wants [b'\x01', ...]; bytes is kinder
            elif isinstance(value, (str, bytes, dict)) or not hasattr(value, '__iter__'):
                raise _type_error(msg_type, name, f'a list of {ftype.base}', value)
            else:
                items = [check(v) for v in value]
            check_length(len(items))
            set_slot(self, slot, items)
        return set_list

    def set_scalar(self: Any, value: Any) -> None:
        set_slot(self, slot, check(value))
    return set_scalar


def _default_factory(field: Field, nested: type | None) -> Callable[[], Any]:
    ftype = field.type
    kind = _kind(ftype, nested)
    if kind == 'sequence':
        code = ARRAY_TYPECODES[ftype.base]
        values = array.array(code, field.default if field.has_default else ())
        return lambda: array.array(code, values)
    if kind == 'fixed':
        dtype = _NATIVE_DTYPES[ftype.base]
        values = np.array(field.default, dtype) if field.has_default else np.zeros(ftype.array_size, dtype)
        return values.copy
    if ftype.is_array:
        if field.has_default:
            values = [_ONE_BYTE[v] for v in field.default] if kind == 'bytes' else list(field.default)
            return values.copy
        if ftype.array == 'fixed':
            size = ftype.array_size
            if nested is not None:
                return lambda: [nested() for _ in range(size)]
            blank = _scalar_blank(ftype.base)
            return lambda: [blank] * size
        return list
    if nested is not None:
        return nested
    value = field.default if field.has_default else _scalar_blank(ftype.base)
    if ftype.base in ('float32', 'float64'):
        value = float(value)
    elif ftype.base == 'byte' and isinstance(value, int):
        value = _ONE_BYTE[value]
    return lambda: value


def _scalar_blank(base: str) -> Any:
    if base == 'bool':
        return False
    if base in ('float32', 'float64'):
        return 0.0
    if base in ('string', 'wstring'):
        return ''
    if base == 'byte':
        return _ONE_BYTE[0]
    return 0


def type_hash(spec: MessageSpec, nested_hashes: dict[str, str]) -> str:
    """A short hash of what goes on the wire: field names and types, nested types by hash.

    The text hashed is the full type name, then `name:type` for each field in order (the type
    as `FieldType.__str__` writes it, plus `@<hash>` of a nested type), joined by ';'; the hash
    is the first 16 hex digits of its SHA-256 (docs/protocol.md has a worked example).
    Comments, constants and defaults are left out, so editing a comment does not make old and
    new nodes refuse each other's messages.
    """
    parts = [spec.full_name]
    for field in spec.fields:
        text = f'{field.name}:{field.type}'
        if not field.type.is_primitive:
            text += '@' + nested_hashes[field.type.base]
        parts.append(text)
    return hashlib.sha256(';'.join(parts).encode()).hexdigest()[:16]


# -- code generation ---------------------------------------------------------------------------
def _wire_error(msg_type: str, what: str) -> DecodeError:
    return DecodeError(f'{msg_type}: {what}')


def _generate_codec(cls: type, spec: MessageSpec, nested: dict[str, type]) -> None:
    """Compile `cls._ENC` and `cls._DEC` (see Message) for this type.

    The decoder takes the header as msgpack-python gives it with `use_list=False` (arrays are
    tuples) and checks each value inline for the common case (`type(v) is float`), falling
    back to the assignment checker, which raises the same error assignment would.
    """
    msg_type = spec.full_name
    env: dict[str, Any] = {
        '_new': object.__new__, '_cls': cls, '_tuple': tuple, '_int': int, '_float': float,
        '_str': str, '_bool': bool, '_bytes': bytes, '_len': len, '_array': array.array,
        '_frombuffer': np.frombuffer, '_F32': _FLOAT32_MAX, '_ONE': _ONE_BYTE,
        '_err': lambda what: _wire_error(msg_type, what),
    }
    has_tail = any(_kind(f.type, nested.get(f.type.base)) in ('sequence', 'fixed')
                   or getattr(nested.get(f.type.base), '_HAS_TAIL', False) for f in spec.fields)
    count = len(spec.fields)
    enc: list[str] = []
    dec: list[str] = [
        f'    if type(d) is not _tuple or _len(d) != {count}:',
        f"        raise _err(f'expected an array of its {count} field(s), got {{type(d).__name__}} "
        f"{{d!r:.40}}')",
        '    m = _new(_cls)',
    ]
    for i, field in enumerate(spec.fields):
        ftype, slot, name = field.type, '_' + field.name, field.name
        sub = nested.get(ftype.base)
        kind = _kind(ftype, sub)
        check = f'_c{i}'
        if kind in ('scalar', 'list', 'bytes') and sub is None:
            env[check] = _scalar_checker(msg_type, name, ftype, None)
        env[f'_len{i}'] = _length_checker(msg_type, name, ftype) if ftype.is_array else None
        dec.append(f'    v = d[{i}]')
        if kind == 'nested':
            env[f'_e{i}'], env[f'_d{i}'] = sub._ENC, (sub._DEC if sub._HAS_TAIL else sub._DEC1)
            enc.append(f'_e{i}(m.{slot}, t)')
            dec.append(f'    m.{slot}, o = _d{i}(v, b, o)' if sub._HAS_TAIL else f'    m.{slot} = _d{i}(v)')
        elif kind == 'scalar':
            enc.append(f'm.{slot}[0]' if ftype.base == 'byte' else f'm.{slot}')
            dec.extend(_scalar_decode(i, ftype, check))
            dec.append(f'    m.{slot} = v')
        elif kind in ('sequence', 'fixed'):
            wire = NUMPY_DTYPES[ftype.base]
            env[f'_dt{i}'], env[f'_code{i}'] = wire, ARRAY_TYPECODES[ftype.base]
            env[f'_native{i}'] = _NATIVE_DTYPES[ftype.base]
            enc.append(f'_put(t, m.{slot})')
            dec.extend([
                '    if type(v) is not _int or v < 0:',
                f"        raise _err(f'{name}: expected an element count, got {{v!r:.40}}')",
                f'    _len{i}(v)',
                f'    e = o + v * {wire.itemsize}',
                '    if e > _len(b):',
                f"        raise _err('{name}: the payload ends inside this array')",
            ])
            if kind == 'sequence':
                dec.extend([f'    a = _array(_code{i})', '    a.frombytes(b[o:e])'])
                if _SWAP and wire.itemsize > 1:
                    dec.append('    a.byteswap()')
            else:
                dec.append(f'    a = _frombuffer(b, _dt{i}, v, o).astype(_native{i})')
            dec.extend([f'    m.{slot} = a', '    o = e'])
        elif kind == 'bytes':
            enc.append(f"b''.join(m.{slot})")
            dec.extend([
                '    if type(v) is not _bytes:',
                f"        raise _err(f'{name}: expected bin (byte[]), got {{type(v).__name__}}')",
                f'    _len{i}(_len(v))',
                f'    m.{slot} = [_ONE[x] for x in v]',
            ])
        else:  # a list of strings, bools or messages
            dec.extend([
                '    if type(v) is not _tuple:',
                f"        raise _err(f'{name}: expected an array, got {{type(v).__name__}}')",
                f'    _len{i}(_len(v))',
            ])
            if sub is not None:
                env[f'_e{i}'], env[f'_d{i}'] = sub._ENC, (sub._DEC if sub._HAS_TAIL else sub._DEC1)
                enc.append(f'[_e{i}(x, t) for x in m.{slot}]')
                if sub._HAS_TAIL:
                    dec.extend(['    l = []', '    for x in v:', f'        x, o = _d{i}(x, b, o)',
                                '        l.append(x)', f'    m.{slot} = l'])
                else:
                    dec.append(f'    m.{slot} = [_d{i}(x) for x in v]')
            else:
                exact = {'bool': '_bool', 'string': '_str', 'wstring': '_str'}[ftype.base]
                enc.append(f'm.{slot}')
                bounded = ftype.string_bound is not None
                dec.append(f'    m.{slot} = [x if type(x) is {exact}{" and _len(x) <= " + str(ftype.string_bound) if bounded else ""}'
                           f' else {check}(x) for x in v]')
    env['_put'] = _put_swapped if _SWAP else _put
    body = ''.join(line + '\n' for line in dec)
    if has_tail:
        decoders = f'def _DEC(d, b, o):\n{body}    return m, o\n'
    else:  # no tail to track: a one-argument decoder, which nesting types call directly
        decoders = f'def _DEC1(d):\n{body}    return m\ndef _DEC(d, b, o):\n    return _DEC1(d), o\n'
    source = f"def _ENC(m, t):\n    return ({''.join(e + ', ' for e in enc)})\n{decoders}"
    exec(compile(source, f'<zros codec {msg_type}>', 'exec'), env)
    cls._ENC = staticmethod(env['_ENC'])
    cls._DEC = staticmethod(env['_DEC'])
    if not has_tail:
        cls._DEC1 = staticmethod(env['_DEC1'])
    cls._HAS_TAIL = has_tail
    cls._ENCODE_CHECKS = tuple(_encode_checks(msg_type, spec, nested))
    cls._LAYOUT = layout([
        ('_' + f.name, None if f.type.is_array else nested.get(f.type.base, f.type.base)) for f in spec.fields])


def _scalar_decode(i: int, ftype: FieldType, check: str) -> list[str]:
    """Inline check of a scalar for the common case; anything else goes to the checker."""
    base = ftype.base
    if base in ('float32', 'float64'):
        cond = 'type(v) is not _float' + (' or not -_F32 <= v <= _F32' if base == 'float32' else '')
        return [f'    if {cond}:', f'        v = {check}(v)']
    if base == 'bool':
        return ['    if type(v) is not _bool:', f'        v = {check}(v)']
    if base in ('string', 'wstring'):
        cond = 'type(v) is not _str' + (f' or _len(v) > {ftype.string_bound}' if ftype.string_bound is not None else '')
        return [f'    if {cond}:', f'        v = {check}(v)']
    low, high = _INT_RANGES[base]
    lines = [f'    if type(v) is not _int or not {low} <= v <= {high}:', f'        v = {check}(v)']
    if base == 'byte':
        lines = ['    if type(v) is not _int or not 0 <= v <= 255:', f'        v = {check}(v)',
                 '    else:', '        v = _ONE[v]']
    return lines


def _put(tail: list, values: Any) -> int:
    tail.append(values)
    return len(values)


def _put_swapped(tail: list, values: Any) -> int:
    swapped = array.array(values.typecode, values) if type(values) is array.array else values.copy()
    swapped.byteswap()
    tail.append(swapped)
    return len(values)


def _encode_checks(msg_type: str, spec: MessageSpec, nested: dict[str, type]):
    """What the setters cannot guarantee because containers can be changed in place: the
    length of bounded sequences and lists, and the items of lists of strings, bools and
    messages. Yields (slot, check(value)) pairs that serialize() runs before encoding."""
    for field in spec.fields:
        ftype, name = field.type, field.name
        sub = nested.get(ftype.base)
        kind = _kind(ftype, sub)
        if kind in ('list', 'bytes'):
            check_length = _length_checker(msg_type, name, ftype)
            check_item = _scalar_checker(msg_type, name, ftype, sub, stand_ins=False)

            def check_list(values: Any, check_length=check_length, check_item=check_item) -> None:
                check_length(len(values))
                for value in values:
                    check_item(value)
            yield '_' + name, check_list
        elif kind == 'sequence' and ftype.array == 'bounded':
            yield '_' + name, lambda values, c=_length_checker(msg_type, name, ftype): c(len(values))
        if sub is not None and kind == 'nested':
            yield from ((f'_{name}.{slot}', check) for slot, check in sub._ENCODE_CHECKS)


def make_message_class(spec: MessageSpec, resolve: Callable[[str], type]) -> type:
    """Build the class for `spec`; `resolve` returns the class of a nested 'pkg/msg/Name'."""
    nested = {base: resolve(base) for base in spec.dependencies()}
    namespace: dict[str, Any] = {
        '__slots__': tuple('_' + f.name for f in spec.fields),
        '__module__': f'interfaces.{spec.package}.{spec.full_name.split("/")[1]}',
        '__qualname__': spec.name,
        '_TYPE': spec.full_name,
        '_FIELDS': tuple(f.name for f in spec.fields),
        '_FIELD_TYPES': {f.name: str(f.type) for f in spec.fields},
        '_HASH': type_hash(spec, {k: v._HASH for k, v in nested.items()}),
        '_SPEC': spec,
        '__doc__': spec.text,
    }
    for const in spec.constants:
        namespace[const.name] = _ONE_BYTE[const.value] if const.type == 'byte' else const.value
    for field in spec.fields:
        setter = _make_setter(spec.full_name, field, nested.get(field.type.base))
        namespace[field.name] = property(operator.attrgetter('_' + field.name), setter)
    cls = type(spec.name, (Message,), namespace)
    cls._DEFAULTS = tuple(
        (f.name, _default_factory(f, nested.get(f.type.base))) for f in spec.fields)
    _generate_codec(cls, spec, nested)
    return cls


def make_service_class(spec: ServiceSpec, request: type, response: type,
                       event: Callable[[], type] | None = None) -> type:
    """A service type is a holder of its Request and Response classes, as in rclpy, and of its
    Event message (service introspection's), which `event` builds on first use: few programs
    introspect, and the event needs service_msgs."""
    namespace = {
        '__module__': f'interfaces.{spec.full_name.split("/")[0]}.srv',
        '_TYPE': spec.full_name, '_SPEC': spec, 'Request': request, 'Response': response,
        '_HASH': hashlib.sha256(f'{request._HASH};{response._HASH}'.encode()).hexdigest()[:16],
        '__doc__': spec.text,
    }
    if event is not None:
        namespace['Event'] = _BuiltOnFirstUse(event)
    return type(spec.full_name.split('/')[-1], (), namespace)


class _BuiltOnFirstUse:
    """A class attribute whose value is built the first time it is read (thread-safe)."""

    def __init__(self, build: Callable[[], Any]) -> None:
        self._build = build
        self._value: Any = None
        self._lock = threading.Lock()

    def __get__(self, instance: Any, owner: type) -> Any:
        if self._value is None:
            with self._lock:
                if self._value is None:
                    self._value = self._build()
        return self._value


def make_action_class(spec: ActionSpec, goal: type, result: type, feedback: type) -> type:
    """An action type holds Goal, Result and Feedback, and its protocol types as `Impl`
    (built on first access, see zros.action_types)."""
    from zros.action_types import ImplAttribute
    namespace = {
        '__module__': f'interfaces.{spec.full_name.split("/")[0]}.action',
        '_TYPE': spec.full_name, '_SPEC': spec, 'Goal': goal, 'Result': result, 'Feedback': feedback,
        '_HASH': hashlib.sha256(f'{goal._HASH};{result._HASH};{feedback._HASH}'.encode()).hexdigest()[:16],
        '__doc__': spec.text, 'Impl': ImplAttribute(),
    }
    return type(spec.full_name.split('/')[-1], (), namespace)


# -- encoding and decoding whole payloads ------------------------------------------------------
_local = threading.local()


def _packer() -> Callable[[Any], bytes]:
    """This thread's msgpack Packer (one per thread: a Packer has one internal buffer)."""
    pack = getattr(_local, 'pack', None)
    if pack is None:
        pack = _local.pack = msgpack.Packer().pack
    return pack


def serialize_parts(msg: Message) -> tuple[bytes, list]:
    """(msgpack header, numeric arrays of the tail) of `msg`: the payload is their
    concatenation. Raises MessageTypeError when a list or bounded sequence was changed in
    place into something its field does not allow."""
    cls = type(msg)
    for slot, check in cls._ENCODE_CHECKS:
        check(operator.attrgetter(slot)(msg))
    tail: list = []
    try:
        head = _packer()(cls._ENC(msg, tail))
    except (TypeError, AttributeError, ValueError, OverflowError) as exc:
        raise MessageTypeError(f'cannot encode {cls._TYPE}: {exc}') from None
    return head, tail


def packed_array(items: list[bytes]) -> bytes:
    """The MessagePack array of `items`, each already packed: an array header then the items,
    so that cached parts of a header are joined instead of packed again."""
    count = len(items)
    if count < 16:
        prefix = bytes((0x90 | count,))
    elif count < 1 << 16:
        prefix = b'\xdc' + count.to_bytes(2, 'big')
    else:
        prefix = b'\xdd' + count.to_bytes(4, 'big')
    return b''.join((prefix, *items))


def serialize(msg: Message) -> bytes:
    """Encode a message to its wire form (docs/protocol.md): header then tail."""
    head, tail = serialize_parts(msg)
    return b''.join((head, *tail)) if tail else head


def _read_header(buffer: memoryview) -> tuple[Any, int]:
    """The msgpack header at the start of `buffer` and where the tail starts. Feeds the
    unpacker a growing prefix, so a large tail is never copied to find the header's end."""
    unpacker = msgpack.Unpacker(use_list=False, raw=False, max_buffer_size=max(len(buffer), 1 << 20),
                                strict_map_key=False)
    fed, step = 0, 4096
    while True:
        unpacker.feed(buffer[fed:fed + step])
        fed += step
        try:
            return unpacker.unpack(), unpacker.tell()
        except msgpack.OutOfData:
            if fed >= len(buffer):
                raise DecodeError('the payload ends inside the msgpack header') from None
            step *= 4


def encoder(cls: type) -> Callable[[Message], bytes]:
    """`serialize` for one class, for a hot path (a publisher): a type without numeric arrays
    and without lists or bounded sequences (whose contents can change in place, so they are
    checked per message) is packed straight from its generated encoder, and a tree of float64
    fields by one struct (zros.fixed_layout)."""
    if cls._LAYOUT is not None:
        return fixed_encoder(cls, lambda exc: MessageTypeError(f'cannot encode {cls._TYPE}: {exc}'))
    if cls._HAS_TAIL or cls._ENCODE_CHECKS:
        return serialize
    encode_header = cls._ENC

    def encode(msg: Message) -> bytes:
        try:
            return _packer()(encode_header(msg, None))
        except (TypeError, AttributeError, ValueError, OverflowError) as exc:
            raise MessageTypeError(f'cannot encode {cls._TYPE}: {exc}') from None
    return encode


def decoder(cls: type) -> Callable[[bytes], Message]:
    """`deserialize` for one class, for a hot path (a subscription): as strict, but a payload
    that fails is decoded again by `deserialize`, which raises DecodeError with the reason; a
    type without numeric arrays is msgpack's unpackb and its generated decoder, nothing more,
    and a tree of float64 fields laid out as msgpack writes it one struct read
    (zros.fixed_layout)."""
    if cls._HAS_TAIL:
        return lambda data: deserialize(data, cls)
    decode_header, unpackb = cls._DEC1, msgpack.unpackb

    def decode(data: bytes) -> Message:
        try:
            return decode_header(unpackb(data, use_list=False, raw=False))
        except Exception:  # noqa: BLE001 - not a valid message: deserialize says why
            return deserialize(data, cls)
    return decode if cls._LAYOUT is None else fixed_decoder(cls, decode)


def deserialize(data: bytes | memoryview, cls: type) -> Message:
    """Decode a payload as `cls`, checking it as assignment would; any mismatch (wrong shape,
    type, range, bound, length, trailing bytes) raises DecodeError with a one-line reason."""
    try:
        if cls._HAS_TAIL:
            buffer = memoryview(data)
            header, at = _read_header(buffer)
            msg, end = cls._DEC(header, buffer, at)
        else:
            msg, end = cls._DEC1(msgpack.unpackb(data, use_list=False, raw=False)), len(data)
        if end != len(data):
            raise DecodeError(f'{len(data) - end} bytes follow the message')
        return msg
    except DecodeError as exc:
        reason = str(exc).removeprefix(f'{cls._TYPE}: ')
        raise DecodeError(f'payload is not a valid {cls._TYPE}: {reason}') from None
    except Exception as exc:  # noqa: BLE001 - any failure here means a corrupt or foreign payload
        raise DecodeError(f'payload is not a valid {cls._TYPE}: {_reason(exc)}') from None


def _reason(exc: Exception) -> str:
    if isinstance(exc, MessageTypeError):
        return str(exc)
    if isinstance(exc, msgpack.ExtraData):
        return 'trailing bytes after the msgpack value'
    return f'{type(exc).__name__}: {exc}'
