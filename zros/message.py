"""Message classes built from parsed interface specs, and their MessagePack codec.

Classes are made at import time from the IDL text (no build step). Each field is a property
over a slot, as in rclpy's generated code: assignment checks the value's type and range and
fails with an error that names the message and the field, so a bad value is caught where the
user wrote it rather than deep inside a publish.

Wire format (docs/protocol.md): one MessagePack map per message, keyed by field name; nested
messages are nested maps; numeric arrays are raw little-endian bytes (MessagePack `bin`) and
come back as numpy arrays over the received buffer (read-only, no copy). The encoder and
decoder of each type are generated Python source compiled once per type, so the hot path has
no per-field dispatch.
"""
from __future__ import annotations

import hashlib
import math
import operator
from typing import Any, Callable

import msgpack
import numpy as np

from zros.errors import DecodeError, MessageTypeError
from zros.idl import ActionSpec, Field, FieldType, MessageSpec, ServiceSpec

__all__ = ['Message', 'MessageArray', 'make_message_class', 'make_service_class', 'make_action_class',
           'NUMPY_DTYPES', 'serialize', 'deserialize']

#: numpy dtype of each numeric primitive, as it travels on the wire (little-endian).
NUMPY_DTYPES: dict[str, np.dtype] = {
    'bool': np.dtype('?'), 'byte': np.dtype('u1'), 'char': np.dtype('u1'),
    'int8': np.dtype('i1'), 'uint8': np.dtype('u1'),
    'int16': np.dtype('<i2'), 'uint16': np.dtype('<u2'),
    'int32': np.dtype('<i4'), 'uint32': np.dtype('<u4'),
    'int64': np.dtype('<i8'), 'uint64': np.dtype('<u8'),
    'float32': np.dtype('<f4'), 'float64': np.dtype('<f8'),
}

_INT_RANGES = {
    'byte': (0, 255), 'char': (0, 255),
    'int8': (-2**7, 2**7 - 1), 'uint8': (0, 2**8 - 1),
    'int16': (-2**15, 2**15 - 1), 'uint16': (0, 2**16 - 1),
    'int32': (-2**31, 2**31 - 1), 'uint32': (0, 2**32 - 1),
    'int64': (-2**63, 2**63 - 1), 'uint64': (0, 2**64 - 1),
}
_FLOAT32_MAX = 3.4028234663852886e38


class MessageArray(np.ndarray):
    """The numpy array of a numeric array field.

    Iterating gives Python numbers (as rclpy's array.array does), so `list(msg.sequence)` and
    `for r in scan.ranges` behave like ROS code expects; everything else is plain numpy.
    """

    def __iter__(self):
        return iter(self.tolist())

    def __repr__(self) -> str:
        return repr(self.view(np.ndarray))


class Message:
    """Base of every generated message class.

    Generated subclasses set `_TYPE` ('pkg/msg/Name'), `_FIELDS` (names in definition order),
    `_FIELD_TYPES` (IDL type text per field), `_HASH` and the codec functions.
    """

    __slots__ = ()
    _TYPE: str = ''
    _FIELDS: tuple[str, ...] = ()
    _FIELD_TYPES: dict[str, str] = {}
    _HASH: str = ''
    _SPEC: MessageSpec
    _DEFAULTS: tuple[tuple[str, Callable[[], Any]], ...] = ()
    _TO_WIRE: Callable[[Any], dict]
    _FROM_WIRE: Callable[[dict], Any]

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
            if isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
                if not np.array_equal(a, b):
                    return False
            elif a != b:
                return False
        return True

    __hash__ = None  # mutable, like rclpy messages

    def __repr__(self) -> str:
        dotted = self._TYPE.replace('/', '.')
        parts = []
        for name in self._FIELDS:
            value = getattr(self, '_' + name)
            if isinstance(value, np.ndarray):
                value = f'array({value.tolist()!r}, dtype={value.dtype.name})'
            else:
                value = repr(value)
            parts.append(f'{name}={value}')
        return f"{dotted}({', '.join(parts)})"

    def __copy__(self) -> 'Message':
        return type(self)._FROM_WIRE(type(self)._TO_WIRE(self))

    def __deepcopy__(self, memo: dict) -> 'Message':
        return type(self)._FROM_WIRE(msgpack.unpackb(msgpack.packb(type(self)._TO_WIRE(self))))


def _type_error(msg_type: str, field: str, expected: str, value: Any) -> MessageTypeError:
    return MessageTypeError(
        f"{msg_type}.{field} must be {expected}, got {type(value).__name__} {value!r:.60}")


def _scalar_checker(msg_type: str, name: str, ftype: FieldType,
                    nested: type | None) -> Callable[[Any], Any]:
    """Return a function that validates and normalises one scalar value of this field."""
    base = ftype.base
    if nested is not None:
        expected = nested._TYPE

        def check_nested(value: Any) -> Any:
            if type(value) is not nested:
                raise _type_error(msg_type, name, f'a {expected} message', value)
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
            if isinstance(value, (float, int, np.floating, np.integer)) and not isinstance(value, bool):
                value = float(value)
                if limit is not None and not math.isinf(value) and abs(value) > limit:
                    raise MessageTypeError(f'{msg_type}.{name} = {value!r} is out of range for float32')
                return value
            raise _type_error(msg_type, name, f'a float ({base})', value)
        return check_float
    if base in _INT_RANGES:
        low, high = _INT_RANGES[base]
        text_ok = base == 'char'

        def check_int(value: Any) -> int:
            if text_ok and isinstance(value, str) and len(value) == 1:
                value = ord(value)
            elif base == 'byte' and isinstance(value, (bytes, bytearray)) and len(value) == 1:
                value = value[0]
            if isinstance(value, (int, np.integer)) and not isinstance(value, bool):
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


def _check_length(msg_type: str, name: str, ftype: FieldType, length: int) -> None:
    if ftype.array == 'fixed' and length != ftype.array_size:
        raise MessageTypeError(
            f'{msg_type}.{name} must have exactly {ftype.array_size} elements, got {length}')
    if ftype.array == 'bounded' and length > ftype.array_size:
        raise MessageTypeError(
            f'{msg_type}.{name} may have at most {ftype.array_size} elements, got {length}')


def _make_setter(msg_type: str, field: Field, nested: type | None) -> Callable[[Any, Any], None]:
    name, ftype, slot = field.name, field.type, '_' + field.name
    set_slot = object.__setattr__
    if ftype.is_array and ftype.base in NUMPY_DTYPES:
        dtype = NUMPY_DTYPES[ftype.base]
        is_int = dtype.kind in 'iu'

        def set_numeric_array(self: Any, value: Any) -> None:
            if isinstance(value, np.ndarray) and value.dtype == dtype and value.ndim == 1:
                array = value if value.flags.c_contiguous else np.ascontiguousarray(value)
            elif isinstance(value, (bytes, bytearray, memoryview)) and dtype.itemsize == 1:
                array = np.frombuffer(value, dtype=dtype)
            else:
                if isinstance(value, (str, bytes)) or not hasattr(value, '__len__'):
                    raise _type_error(msg_type, name, f'a sequence of {ftype.base}', value)
                try:
                    probe = np.asarray(value)
                    if is_int and probe.size and probe.dtype.kind not in 'iub':
                        raise _type_error(msg_type, name, f'a sequence of {ftype.base} (ints)', value)
                    if dtype.kind == 'b' and probe.size and probe.dtype.kind != 'b':
                        raise _type_error(msg_type, name, 'a sequence of bool', value)
                    if dtype.kind == 'f' and probe.size and probe.dtype.kind not in 'iufO':
                        raise _type_error(msg_type, name, f'a sequence of {ftype.base} (numbers)', value)
                    if (dtype == NUMPY_DTYPES['float32'] and probe.dtype.kind == 'f'
                            and np.any(np.abs(probe[np.isfinite(probe)]) > _FLOAT32_MAX)):
                        raise MessageTypeError(f'{msg_type}.{name} has values out of range for float32')
                    array = np.ascontiguousarray(probe, dtype=dtype) if probe.size else np.zeros(0, dtype)
                    if is_int and probe.size and (probe.min() < np.iinfo(dtype).min or probe.max() > np.iinfo(dtype).max):
                        raise MessageTypeError(f'{msg_type}.{name} has values out of range for {ftype.base}')
                except (OverflowError, ValueError, TypeError) as exc:
                    if isinstance(exc, MessageTypeError):
                        raise
                    raise MessageTypeError(f'{msg_type}.{name}: {exc}') from None
                if array.ndim != 1:
                    raise MessageTypeError(f'{msg_type}.{name} must be one-dimensional')
            _check_length(msg_type, name, ftype, len(array))
            set_slot(self, slot, array.view(MessageArray))
        return set_numeric_array
    check = _scalar_checker(msg_type, name, ftype, nested)
    if ftype.is_array:
        def set_list(self: Any, value: Any) -> None:
            if isinstance(value, (str, bytes)) or not hasattr(value, '__iter__'):
                raise _type_error(msg_type, name, f'a list of {ftype.base}', value)
            items = [check(v) for v in value]
            _check_length(msg_type, name, ftype, len(items))
            set_slot(self, slot, items)
        return set_list

    def set_scalar(self: Any, value: Any) -> None:
        set_slot(self, slot, check(value))
    return set_scalar


def _default_factory(field: Field, nested: type | None) -> Callable[[], Any]:
    ftype = field.type
    if ftype.is_array:
        if ftype.base in NUMPY_DTYPES:
            dtype = NUMPY_DTYPES[ftype.base]
            if field.has_default:
                values = np.array(field.default, dtype=dtype).view(MessageArray)
                return values.copy
            size = ftype.array_size if ftype.array == 'fixed' else 0
            return lambda: np.zeros(size, dtype).view(MessageArray)
        if field.has_default:
            values = list(field.default)
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
    return lambda: value


def _scalar_blank(base: str) -> Any:
    if base == 'bool':
        return False
    if base in ('float32', 'float64'):
        return 0.0
    if base in ('string', 'wstring'):
        return ''
    return 0


def type_hash(spec: MessageSpec, nested_hashes: dict[str, str]) -> str:
    """A short hash of what goes on the wire: field names and types, nested types by hash.

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


def _generate_codec(cls: type, spec: MessageSpec, nested: dict[str, type]) -> None:
    """Compile `cls._TO_WIRE` (message -> plain dict) and `cls._FROM_WIRE` (dict -> message)."""
    env: dict[str, Any] = {'_new': object.__new__, '_frombuffer': np.frombuffer, '_cls': cls,
                           '_memoryview': memoryview, '_MessageArray': MessageArray}
    enc, dec = [], []
    for i, field in enumerate(spec.fields):
        ftype, slot, key = field.type, '_' + field.name, field.name
        sub = nested.get(ftype.base)
        if sub is not None:
            env[f'_enc{i}'], env[f'_dec{i}'] = sub._TO_WIRE, sub._FROM_WIRE
            if ftype.is_array:
                enc.append(f'{key!r}: [_enc{i}(x) for x in m.{slot}]')
                dec.append(f'm.{slot} = [_dec{i}(x) for x in d[{key!r}]]')
            else:
                enc.append(f'{key!r}: _enc{i}(m.{slot})')
                dec.append(f'm.{slot} = _dec{i}(d[{key!r}])')
        elif ftype.is_array and ftype.base in NUMPY_DTYPES:
            env[f'_dt{i}'] = NUMPY_DTYPES[ftype.base]
            enc.append(f'{key!r}: _memoryview(m.{slot})')
            dec.append(f'm.{slot} = _frombuffer(d[{key!r}], _dt{i}).view(_MessageArray)')
        elif ftype.is_array:
            enc.append(f'{key!r}: m.{slot}')
            dec.append(f'm.{slot} = list(d[{key!r}])')
        else:
            enc.append(f'{key!r}: m.{slot}')
            dec.append(f'm.{slot} = d[{key!r}]')
    source = (
        'def _TO_WIRE(m):\n'
        f"    return {{{', '.join(enc)}}}\n"
        'def _FROM_WIRE(d):\n'
        '    m = _new(_cls)\n'
        + ''.join(f'    {line}\n' for line in dec)
        + '    return m\n'
    )
    exec(compile(source, f'<zros codec {spec.full_name}>', 'exec'), env)
    cls._TO_WIRE = staticmethod(env['_TO_WIRE'])
    cls._FROM_WIRE = staticmethod(env['_FROM_WIRE'])


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
        namespace[const.name] = const.value
    for field in spec.fields:
        setter = _make_setter(spec.full_name, field, nested.get(field.type.base))
        namespace[field.name] = property(operator.attrgetter('_' + field.name), setter)
    cls = type(spec.name, (Message,), namespace)
    cls._DEFAULTS = tuple(
        (f.name, _default_factory(f, nested.get(f.type.base))) for f in spec.fields)
    _generate_codec(cls, spec, nested)
    return cls


def make_service_class(spec: ServiceSpec, request: type, response: type) -> type:
    """A service type is a holder of its Request and Response classes, as in rclpy."""
    return type(spec.full_name.split('/')[-1], (), {
        '__module__': f'interfaces.{spec.full_name.split("/")[0]}.srv',
        '_TYPE': spec.full_name, '_SPEC': spec, 'Request': request, 'Response': response,
        '_HASH': hashlib.sha256(f'{request._HASH};{response._HASH}'.encode()).hexdigest()[:16],
        '__doc__': spec.text,
    })


def make_action_class(spec: ActionSpec, goal: type, result: type, feedback: type) -> type:
    """An action type holds Goal, Result and Feedback (zros.action adds its protocol types)."""
    namespace = {
        '__module__': f'interfaces.{spec.full_name.split("/")[0]}.action',
        '_TYPE': spec.full_name, '_SPEC': spec, 'Goal': goal, 'Result': result, 'Feedback': feedback,
        '_HASH': hashlib.sha256(f'{goal._HASH};{result._HASH};{feedback._HASH}'.encode()).hexdigest()[:16],
        '__doc__': spec.text,
    }
    return type(spec.full_name.split('/')[-1], (), namespace)


def serialize(msg: Message) -> bytes:
    """Encode a message to its MessagePack wire form."""
    return msgpack.packb(msg._TO_WIRE(msg))


def deserialize(data: bytes | memoryview, cls: type) -> Message:
    """Decode a MessagePack payload as `cls`; any mismatch raises DecodeError."""
    try:
        return cls._FROM_WIRE(msgpack.unpackb(data))
    except Exception as exc:  # noqa: BLE001 - any failure here means a corrupt or foreign payload
        raise DecodeError(f'payload is not a valid {cls._TYPE}: {type(exc).__name__}: {exc}') from None
