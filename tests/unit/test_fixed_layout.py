"""zros.fixed_layout: the struct codec of float64 trees (Twist, Pose, ...) writes the bytes
msgpack writes, reads them back to equal messages, and hands every other layout to the generic
strict decoder, so the wire format and what is accepted or refused do not change."""
from __future__ import annotations

import math
import struct

import msgpack
import pytest
from hypothesis import given
from hypothesis import strategies as st

from zros.errors import DecodeError, MessageTypeError
from zros.message import decoder, deserialize, encoder, serialize

from interfaces.geometry_msgs.msg import (Point32, Pose, PoseStamped, Quaternion, Transform, Twist,
                                          Vector3, Wrench)
from interfaces.std_msgs.msg import Float64, Int32, String

doubles = st.floats(allow_nan=True, allow_infinity=True)


def _same(a: float, b: float) -> bool:
    """Equal as doubles, NaN and the sign of zero included."""
    return struct.pack('>d', a) == struct.pack('>d', b)


@pytest.mark.parametrize('cls, fixed', [
    (Twist, True), (Pose, True), (Vector3, True), (Quaternion, True), (Transform, True),
    (Wrench, True), (Float64, True),
    (Point32, False),       # float32: checked against float32's range on the way in
    (PoseStamped, False),   # a header: a string and ints
    (Int32, False), (String, False),
])
def test_only_trees_of_float64_fields_have_a_fixed_layout(cls, fixed):
    assert (cls._LAYOUT is not None) is fixed


@given(st.tuples(*[doubles] * 6))
def test_a_twist_is_written_byte_for_byte_as_msgpack_writes_it_and_read_back(values):
    twist = Twist(linear=Vector3(x=values[0], y=values[1], z=values[2]),
                  angular=Vector3(x=values[3], y=values[4], z=values[5]))
    payload = encoder(Twist)(twist)
    assert payload == msgpack.packb([list(values[:3]), list(values[3:])]) == serialize(twist)
    back = decoder(Twist)(payload)
    assert type(back) is Twist and type(back.linear) is Vector3
    got = (back.linear.x, back.linear.y, back.linear.z, back.angular.x, back.angular.y, back.angular.z)
    assert all(_same(a, b) for a, b in zip(got, values))


@given(st.tuples(*[st.floats(allow_nan=False)] * 7))
def test_a_pose_two_levels_deep_round_trips_and_the_generic_decoder_agrees(values):
    pose = Pose()
    pose.position.x, pose.position.y, pose.position.z = values[:3]
    pose.orientation.x, pose.orientation.y, pose.orientation.z, pose.orientation.w = values[3:]
    payload = encoder(Pose)(pose)
    assert payload == serialize(pose)
    assert decoder(Pose)(payload) == pose == deserialize(payload, Pose)


def test_whole_numbers_packed_as_ints_by_another_sender_take_the_generic_decoder():
    payload = msgpack.packb([[1, 2.0, 3.0], [0.0, 0.0, 1]])
    assert decoder(Twist)(payload) == Twist(linear=Vector3(x=1.0, y=2.0, z=3.0),
                                            angular=Vector3(x=0.0, y=0.0, z=1.0))


def test_a_bool_where_a_float_belongs_is_refused_as_before():
    with pytest.raises(DecodeError, match='Twist'):
        decoder(Twist)(msgpack.packb([[1.0, 2.0, 3.0], [0.0, 0.0, True]]))


def test_a_payload_of_the_right_size_with_wrong_markers_is_refused_with_the_reason():
    good = encoder(Twist)(Twist())
    bad = b'\x92\x94' + good[2:]   # the first Vector3 claims four fields
    with pytest.raises(DecodeError, match='Twist'):
        decoder(Twist)(bad)
    with pytest.raises(DecodeError, match='Twist'):
        decoder(Twist)(good + b'\x00')   # a trailing byte


def test_a_slot_written_past_the_setters_fails_in_one_line():
    twist = Twist()
    object.__setattr__(twist.linear, '_x', 'not a float')
    with pytest.raises(MessageTypeError, match='cannot encode geometry_msgs/msg/Twist'):
        encoder(Twist)(twist)


def test_float64_scalar_message():
    payload = encoder(Float64)(Float64(data=-0.0))
    assert payload == b'\x91\xcb' + struct.pack('>d', -0.0)
    assert math.copysign(1.0, decoder(Float64)(payload).data) == -1.0
