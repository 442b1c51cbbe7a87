"""CDR values at the edges of what rosbags and zros represent alike (the round trip of every
shipped type with generated values: tests/unit/test_round_trips.py)."""
from __future__ import annotations

import pytest

from zros.bag.cdr import CdrCodec
from zros.bag.errors import BagError

from interfaces.diagnostic_msgs.msg import DiagnosticStatus
from interfaces.example_interfaces.msg import WString
from interfaces.rcl_interfaces.msg import ParameterType
from interfaces.std_msgs.msg import Empty

#: The encapsulation header of little-endian plain CDR.
HEADER = b'\x00\x01\x00\x00'


def test_a_message_without_fields_is_rosidls_one_zero_byte():
    """rosidl gives a message without fields one uint8 member (a C struct cannot be empty), so
    ROS 2 writes std_msgs/Empty as the header and one zero byte."""
    codec = CdrCodec()
    assert codec.serialize(Empty()) == HEADER + b'\x00'
    assert codec.deserialize(HEADER + b'\x00', Empty) == Empty()
    assert codec.deserialize(codec.serialize(ParameterType()), ParameterType) == ParameterType()


def test_a_byte_above_127_is_the_same_octet():
    """A `byte` is an octet 0..255 in ROS 2 and zros; rosbags holds it as an int8."""
    codec = CdrCodec()
    data = codec.serialize(DiagnosticStatus(level=b'\x80'))
    assert data[len(HEADER)] == 0x80
    assert codec.deserialize(data, DiagnosticStatus).level == b'\x80'


def test_a_type_with_a_wstring_field_is_refused_with_the_reason():
    """rosbags' msg grammar has no wstring (it took one for a message type and failed with a
    KeyError); the bag commands print this error as their one line."""
    with pytest.raises(BagError, match=r'example_interfaces/msg/WString: rosbags .* has no wstring'):
        CdrCodec().serialize(WString(data='x'))
