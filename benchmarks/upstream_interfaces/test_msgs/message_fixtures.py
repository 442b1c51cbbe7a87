"""Sample messages of each test_msgs type (what rcl_interfaces's test_msgs ships as
`test_msgs.message_fixtures` and rclpy's serialization tests round-trip).

    from test_msgs.message_fixtures import get_test_msg
    for msg in get_test_msg('Arrays'): ...

Each list holds the type's defaults first, then messages that reach the ends of every field's
range (the smallest and largest integers, floats exactly representable as float32, empty and
non-ASCII text), so a codec that truncates, reorders or misaligns shows.
"""
from __future__ import annotations

from typing import Any, Callable

from test_msgs import msg

__all__ = ['get_test_msg']

#: basic type -> (low end, middle, high end); floats are exact in float32
_RANGES: dict[str, tuple[Any, Any, Any]] = {
    'bool': (False, True, False), 'byte': (b'\x00', b'\x01', b'\xff'), 'char': (0, 1, 127),
    'float32': (-2.5, 0.0, 1.125), 'float64': (-3.1415, 0.0, 1e300), 'int8': (-128, 0, 127), 'uint8': (0, 1, 255),
    'int16': (-32768, 0, 32767), 'uint16': (0, 1, 65535), 'int32': (-2**31, 0, 2**31 - 1),
    'uint32': (0, 1, 2**32 - 1), 'int64': (-2**63, 0, 2**63 - 1), 'uint64': (0, 1, 2**64 - 1),
}
_TEXT = ('', 'max value', 'Hellö wörld! ハロー')


def _basic_types(pick: int) -> Any:
    return msg.BasicTypes(**{f'{t}_value': values[pick] for t, values in _RANGES.items()})


def _defaults(pick: int) -> Any:
    return msg.Defaults(**{f'{t}_value': values[pick] for t, values in _RANGES.items()})


def _containers(cls: type, count: int) -> list[Any]:
    """`cls` (Arrays, BoundedSequences or UnboundedSequences) as it comes, and filled with
    `count` items per container, taken from the ranges in turn."""
    def items(values: tuple) -> list:
        return [values[i % 3] for i in range(count)]
    filled = cls(
        **{f'{t}_values': items(values) for t, values in _RANGES.items()},
        string_values=items(_TEXT),
        basic_types_values=[_basic_types(i % 3) for i in range(count)],
        constants_values=[msg.Constants() for _ in range(count)],
        defaults_values=[_defaults(i % 3) for i in range(count)],
        alignment_check=-7)
    return [cls(), filled]


def _multi_nested() -> list[Any]:
    arrays, bounded, unbounded = (_containers(cls, n)[1] for cls, n in (
        (msg.Arrays, 3), (msg.BoundedSequences, 3), (msg.UnboundedSequences, 2)))
    full = msg.MultiNested(
        array_of_arrays=[arrays] * 3, array_of_bounded_sequences=[bounded] * 3,
        array_of_unbounded_sequences=[unbounded] * 3, bounded_sequence_of_arrays=[arrays],
        bounded_sequence_of_bounded_sequences=[bounded] * 2, bounded_sequence_of_unbounded_sequences=[unbounded],
        unbounded_sequence_of_arrays=[arrays] * 4, unbounded_sequence_of_bounded_sequences=[bounded],
        unbounded_sequence_of_unbounded_sequences=[unbounded] * 2)
    return [msg.MultiNested(), full]


def _builtins() -> list[Any]:
    from builtin_interfaces.msg import Duration, Time
    return [msg.Builtins(), msg.Builtins(duration_value=Duration(sec=-1234567890, nanosec=123456789),
                                         time_value=Time(sec=-1234567890, nanosec=987654321))]


def _strings() -> list[Any]:
    return [msg.Strings(), *(msg.Strings(string_value=text, string_value_default1=text[::-1],
                                         bounded_string_value=text[:22]) for text in _TEXT)]


def _wstrings() -> list[Any]:
    return [msg.WStrings(), msg.WStrings(wstring_value='ハローワールド', array_of_wstrings=list(_TEXT),
                                         bounded_sequence_of_wstrings=list(_TEXT[1:]),
                                         unbounded_sequence_of_wstrings=list(_TEXT) * 2)]


_FIXTURES: dict[str, Callable[[], list[Any]]] = {
    'Arrays': lambda: _containers(msg.Arrays, 3),
    'BasicTypes': lambda: [_basic_types(pick) for pick in range(3)],
    'BoundedSequences': lambda: [*_containers(msg.BoundedSequences, 3), msg.BoundedSequences(int8_values=[-1])],
    'Builtins': _builtins,
    'Constants': lambda: [msg.Constants()],
    'Defaults': lambda: [msg.Defaults(), *(_defaults(pick) for pick in range(3))],
    'Empty': lambda: [msg.Empty()],
    'MultiNested': _multi_nested,
    'Nested': lambda: [msg.Nested(basic_types_value=_basic_types(pick)) for pick in range(3)],
    'Strings': _strings,
    'UnboundedSequences': lambda: [*_containers(msg.UnboundedSequences, 5), msg.UnboundedSequences(uint64_values=[])],
    'WStrings': _wstrings,
}


def get_test_msg(message_name: str) -> list[Any]:
    """Fresh sample messages of `test_msgs/msg/<message_name>`.

    Raises:
        KeyError: there are no samples of that type.
    """
    return _FIXTURES[message_name]()
