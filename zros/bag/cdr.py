"""CDR, ROS 2's own serialization, for bags that ROS tools read and for bags ROS 2 recorded.

zros sends MessagePack; rosbag2, Foxglove, PlotJuggler, `rosbags` and `mcap_ros2` expect CDR.
The CDR work is done by rosbags' typestore (a well-kept, tested codec) rather than by hand: its
types are built from zros's own definitions (the concatenated `ros2msg` text that bags carry),
so any type on the zros interface path can be written and read as CDR, and the RIHS01 type hash
ROS 2 stores in its bags comes out of the same definitions.

A zros message is converted to a rosbags message (and back) field by field, driven by the
type's field list: numeric arrays become numpy arrays of the field's dtype whatever they were
(numpy, `array.array`, list, bytes), nested messages recurse.
"""
from __future__ import annotations

import re
from functools import lru_cache
from typing import Any

import numpy as np

from zros.bag.errors import BagError

__all__ = ['CdrCodec', 'CDR_ENCODING']

#: The MCAP message encoding / rosbag2 serialization format of CDR payloads.
CDR_ENCODING = 'cdr'

# rosbags' node kinds in a field description (rosbags.typesys.base.Nodetype values).
_BASE, _NAME, _ARRAY, _SEQUENCE = 1, 2, 3, 4

# The uint8 member rosidl (and so rosbags) gives a message without fields (std_msgs/Empty,
# rcl_interfaces/ParameterType: constants only), as a C struct cannot be empty; it is always 0
# and zros's messages do not have it.
_EMPTY_STRUCT_MEMBER = 'structure_needs_at_least_one_member'

# A `wstring` field in a ros2msg definition (rosbags' msg grammar has no wstring: it would take
# it for a message type named `wstring` and fail later with a KeyError).
_WSTRING_FIELD = re.compile(r'^\s*wstring(<=[0-9]+)?(\[[^\]]*\])?\s', re.MULTILINE)

# numpy dtypes of the numeric primitives, by the names rosbags' field lists use.
_DTYPES = {
    'bool': np.dtype('?'), 'byte': np.dtype('u1'), 'char': np.dtype('u1'), 'octet': np.dtype('u1'),
    'int8': np.dtype('i1'), 'uint8': np.dtype('u1'), 'int16': np.dtype('<i2'), 'uint16': np.dtype('<u2'),
    'int32': np.dtype('<i4'), 'uint32': np.dtype('<u4'), 'int64': np.dtype('<i8'), 'uint64': np.dtype('<u8'),
    'float32': np.dtype('<f4'), 'float64': np.dtype('<f8'),
}


@lru_cache(maxsize=None)
def _store_name(type_name: str) -> str:
    """The typestore's key for `type_name`: a service's or action's parts ('pkg/srv/Name_Request')
    are filed as messages of their package ('pkg/msg/Name_Request'), so that rosbags resolves the
    package-relative type names in their definitions ('ParameterValue[] values') as in a .msg."""
    package, kind, name = (type_name.split('/') + ['', ''])[:3]
    return f'{package}/msg/{name}' if name and kind != 'msg' else type_name


class CdrCodec:
    """Serializes zros messages to CDR and back, for any type zros knows.

    One codec keeps one typestore; types are registered on first use. Not thread-safe: each
    recorder, player or converter owns its codec.
    """

    def __init__(self) -> None:
        from rosbags.typesys import Stores, get_typestore
        self._store = get_typestore(Stores.EMPTY)
        self._classes: dict[str, type] = {}

    # -- types --------------------------------------------------------------------------------
    def register(self, type_name: str) -> None:
        """Make `type_name` ('pkg/msg/Name') and every type it uses known to the typestore.

        Raises:
            InterfaceNotFoundError: zros does not know the type.
            BagError: rosbags cannot parse its definition.
        """
        if _store_name(type_name) in self._store.fielddefs:
            return
        from rosbags.typesys import get_types_from_msg
        from rosbags.typesys.base import TypesysError

        from zros.bag.definition import message_definition
        definition = message_definition(type_name)
        if _WSTRING_FIELD.search(definition):
            raise BagError(f'cannot build a CDR codec for {type_name}: rosbags (which zros uses for CDR) '
                           f'has no wstring, and a field of it is one; record it with --format msgpack')
        try:
            types = get_types_from_msg(definition, _store_name(type_name))
            self._store.register({k: v for k, v in types.items() if k not in self._store.fielddefs})
        except TypesysError as exc:
            raise BagError(f'cannot build a CDR codec for {type_name}: {exc}') from None

    def rihs01(self, type_name: str) -> str:
        """ROS 2's type hash of `type_name` ('RIHS01_<64 hex>'), from zros's definition."""
        self.register(type_name)
        return self._store.hash_rihs01(_store_name(type_name))

    def definition(self, type_name: str) -> str:
        """The concatenated ros2msg definition rosbag2 stores with a topic."""
        from zros.bag.definition import message_definition
        return message_definition(type_name)

    # -- zros -> CDR --------------------------------------------------------------------------
    def serialize(self, msg: Any) -> bytes:
        """CDR bytes (little-endian, with the 4-byte encapsulation header) of a zros message."""
        type_name = msg._TYPE
        self.register(type_name)
        key = _store_name(type_name)
        return bytes(self._store.serialize_cdr(self._to_store(msg, key), key, little_endian=True))

    def _to_store(self, msg: Any, type_name: str) -> Any:
        _, fields = self._store.fielddefs[type_name]
        values = {}
        for name, (kind, detail) in fields:
            if name == _EMPTY_STRUCT_MEMBER:
                values[name] = 0
                continue
            values[name] = self._value_to_store(getattr(msg, name), kind, detail)
        return self._store.types[type_name](**values)

    def _value_to_store(self, value: Any, kind: int, detail: Any) -> Any:
        if kind == _BASE:
            if isinstance(value, bytes):
                # a `byte` is a 1-byte bytes in zros, and a signed int8 in rosbags (the same octet)
                return int.from_bytes(value, 'little', signed=True)
            return value
        if kind == _NAME:
            return self._to_store(value, detail)
        (element_kind, element), _ = detail
        if element_kind == _BASE and element[0] in _DTYPES:
            dtype = _DTYPES[element[0]]
            if isinstance(value, list) and value and isinstance(value[0], bytes):
                value = b''.join(value)  # byte[]: a list of 1-byte bytes in zros
            if isinstance(value, (bytes, bytearray, memoryview)):
                return np.frombuffer(value, dtype=np.uint8).view(dtype)
            return np.asarray(value, dtype=dtype)
        if element_kind == _NAME:
            return [self._to_store(item, element) for item in value]
        return list(value)

    # -- CDR -> zros --------------------------------------------------------------------------
    def deserialize(self, data: bytes | memoryview, msg_type: type) -> Any:
        """A zros message of class `msg_type` from CDR bytes.

        Raises:
            BagError: the bytes are not a CDR `msg_type` (wrong type, truncated, corrupt).
        """
        from rosbags.serde import SerdeError
        type_name = msg_type._TYPE
        self.register(type_name)
        try:
            stored = self._store.deserialize_cdr(data, _store_name(type_name))
        except (SerdeError, ValueError, IndexError) as exc:
            raise BagError(f'not a valid CDR {type_name}: {exc}') from None
        return self._from_store(stored, msg_type)

    def _from_store(self, stored: Any, msg_type: type) -> Any:
        from zros.typesupport import get_message
        msg = msg_type()
        _, fields = self._store.fielddefs[_store_name(msg_type._TYPE)]
        for name, (kind, detail) in fields:
            if name == _EMPTY_STRUCT_MEMBER:
                continue
            value = getattr(stored, name)
            if kind == _NAME:
                value = self._from_store(value, get_message(detail))
            elif kind == _BASE and detail[0] == 'byte':
                value = (value & 0xFF).to_bytes(1, 'little')   # rosbags' int8 back to the octet
            elif kind in (_ARRAY, _SEQUENCE):
                (element_kind, element), _ = detail
                if element_kind == _NAME:
                    element_type = get_message(element)
                    value = [self._from_store(item, element_type) for item in value]
                elif element_kind == _BASE and element[0] in _DTYPES:
                    value = np.asarray(value).view(_DTYPES[element[0]])
                else:
                    value = list(value)
            setattr(msg, name, value)
        return msg
