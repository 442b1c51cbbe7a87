"""A faster codec for the messages whose MessagePack form has one fixed size and layout: trees
of float64 fields (Twist, Vector3, Point, Quaternion, Pose, Transform, Accel, Wrench, ...), the
commonest small messages on a robot.

Why it exists: a message on a round trip is encoded and decoded once, with cold caches, where
every Python call and every intermediate object costs several times its warm price.
msgpack's generic unpacker builds a tuple per nested message, and the generated decoder
(zros.message) takes one call per nested message; a Twist went through four calls and three
tuples. A float64 tree's MessagePack bytes never vary in shape: a fixarray marker per message,
then for each field either a nested message or 0xcb and the value as a big-endian double. So
one precompiled `struct` writes or reads the whole message, and another reads every marker
byte at once to check them.

The bytes written are the ones msgpack writes for the same values (it packs every Python float
as a double), so the wire format does not change and nothing that reads it (other zros
versions, the bridges, a recorded bag) can tell. A payload laid out any other way (another
sender that packs 1.0 as the integer 1, a float32, a map) fails the check and goes to the
generic decoder, which accepts or refuses it exactly as before.
"""
from __future__ import annotations

import struct
from typing import Any, Callable

__all__ = ['layout', 'fixed_encoder', 'fixed_decoder']

#: A message's layout: (slot, None for a float64 field or the nested message class) per field.
Layout = tuple[tuple[str, Any], ...]

_FLOAT64 = 0xcb      # msgpack's marker of a big-endian double
_FIXARRAY = 0x90     # msgpack's marker of an array of up to 15 items, ORed with the count
_MAX_FIXARRAY = 15


def layout(fields: list[tuple[str, Any]]) -> Layout | None:
    """The fixed layout of a message, or None when it has none.

    Args:
        fields: (slot, kind) per field in definition order, where kind is the string 'float64'
            for a float64 scalar, a nested message class for a nested message (which must
            have a layout of its own, its `_LAYOUT`), or anything else for any other field.

    Returns:
        The layout; None for a message with another kind of field, with no fields, or with more
        than 15 (a longer array's marker is 3 bytes: still fixed, but no common message has one).
    """
    if not fields or len(fields) > _MAX_FIXARRAY:
        return None
    out = []
    for slot, kind in fields:
        if kind == 'float64':
            out.append((slot, None))
        elif isinstance(kind, type) and getattr(kind, '_LAYOUT', None) is not None:
            out.append((slot, kind))
        else:
            return None
    return tuple(out)


class _Plan:
    """The byte plan of one layout, walked once: markers and values in wire order."""

    def __init__(self, cls: type) -> None:
        self.encode_format = ['>']   # markers as 'B' (written), values as 'd'
        self.decode_format = ['>']   # markers skipped ('x': checked apart), values 'd'
        self.marks_format = ['>']    # markers read ('B'), values skipped
        self.encode_args: list[str] = []
        self.marks: list[int] = []
        self.size = 0
        self.classes: dict[str, type] = {}
        self.reads: list[str] = []    # source lines of the encoder: nested objects into locals
        self.builds: list[str] = []   # source lines of the decoder: values into new messages
        self._values = 0
        self._messages = 0
        self._walk(cls, 'm')

    def _marker(self, byte: int) -> None:
        self.encode_format.append('B')
        self.decode_format.append('x')
        self.marks_format.append('B')
        self.encode_args.append(str(byte))
        self.marks.append(byte)
        self.size += 1

    def _walk(self, cls: type, name: str) -> None:
        fields = cls._LAYOUT
        self.classes[f'_k_{name}'] = cls
        self._marker(_FIXARRAY | len(fields))
        self.builds.append(f'    {name} = _new(_k_{name})')
        for slot, nested in fields:
            if nested is None:
                self._marker(_FLOAT64)
                self.encode_format.append('d')
                self.decode_format.append('d')
                self.marks_format.append('8x')
                self.encode_args.append(f'{name}.{slot}')
                self.size += 8
                self.builds.append(f'    {name}.{slot} = v{self._values}')
                self._values += 1
            else:
                self._messages += 1
                inner = f'n{self._messages}'
                self.reads.append(f'    {inner} = {name}.{slot}')
                self._walk(nested, inner)
                self.builds.append(f'    {name}.{slot} = {inner}')

    @property
    def values(self) -> str:
        return ''.join(f'v{i}, ' for i in range(self._values))


def fixed_encoder(cls: type, error: Callable[[Exception], Exception]) -> Callable[[Any], bytes]:
    """The encoder of a class with a layout: message -> the bytes msgpack would write.

    Args:
        cls: A message class whose `_LAYOUT` is not None.
        error: Makes the exception raised when a message cannot be encoded (a field that holds
            no float: only code that writes slots past the setters can cause that).
    """
    plan = _Plan(cls)
    env: dict[str, Any] = {'_pack': struct.Struct(''.join(plan.encode_format)).pack, '_error': error}
    source = ('def encode(m):\n    try:\n' + ''.join('    ' + line + '\n' for line in plan.reads)
              + f"        return _pack({', '.join(plan.encode_args)})\n"
              + '    except (struct_error, AttributeError) as exc:\n        raise _error(exc) from None\n')
    env['struct_error'] = struct.error
    exec(compile(source, f'<zros fixed encoder {cls._TYPE}>', 'exec'), env)
    return env['encode']


def fixed_decoder(cls: type, other: Callable[[bytes], Any]) -> Callable[[bytes], Any]:
    """The decoder of a class with a layout: the bytes of a message laid out as msgpack writes
    it become the message in one `struct` read; any other payload goes to `other` (the generic
    strict decoder), so what is accepted and refused does not change.

    Args:
        cls: A message class whose `_LAYOUT` is not None.
        other: The decoder for payloads of another layout.
    """
    plan = _Plan(cls)
    env: dict[str, Any] = {
        '_unpack': struct.Struct(''.join(plan.decode_format)).unpack, '_other': other,
        '_marks': struct.Struct(''.join(plan.marks_format)).unpack, '_MARKS': tuple(plan.marks),
        '_new': object.__new__, '_len': len, **plan.classes}
    source = ('def decode(b):\n'
              f'    if _len(b) != {plan.size} or _marks(b) != _MARKS:\n'
              '        return _other(b)\n'
              f'    {plan.values}= _unpack(b)\n'
              + ''.join(line + '\n' for line in plan.builds)
              + '    return m\n')
    exec(compile(source, f'<zros fixed decoder {cls._TYPE}>', 'exec'), env)
    return env['decode']

