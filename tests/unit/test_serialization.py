"""rclpy.serialization: serialize_message gives ROS 2's CDR bytes, and deserialize_message
reads them back (pure: no session)."""
from __future__ import annotations

import pytest

from zros.serialization import deserialize_message, serialize_message

from interfaces.geometry_msgs.msg import Vector3
from interfaces.std_msgs.msg import String


def test_a_string_is_cdr_with_its_header_length_and_terminator():
    data = serialize_message(String(data='hi'))
    assert data == b'\x00\x01\x00\x00' + b'\x03\x00\x00\x00' + b'hi\x00'
    assert deserialize_message(data, String) == String(data='hi')


def test_round_trip_keeps_float64_values():
    vector = Vector3(x=1.5, y=-2.25, z=1e-9)
    assert deserialize_message(serialize_message(vector), Vector3) == vector


def test_only_messages_are_serialized():
    with pytest.raises(TypeError):
        serialize_message('not a message')
    with pytest.raises(TypeError):
        deserialize_message(b'', str)
