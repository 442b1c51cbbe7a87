"""Message classes built from the IDL, their checks, and the MessagePack codec."""
from __future__ import annotations

import array
import copy
import itertools
import re
import sys

import msgpack
import numpy as np
import pytest

from zros import typesupport
from zros.errors import DecodeError, MessageTypeError
from zros.idl import FieldType
from zros.message import deserialize, serialize

from interfaces.geometry_msgs.msg import Point, Pose, PoseWithCovariance, Twist, Vector3
from interfaces.sensor_msgs.msg import Image, LaserScan
from interfaces.std_msgs.msg import Header, Int32, String, UInt8MultiArray

_unique = itertools.count()


# -- construction, defaults, equality, repr ---------------------------------------------------
def test_keyword_construction_and_defaults():
    assert String().data == ''
    assert String(data='x').data == 'x'
    twist = Twist(linear=Vector3(x=1.0, y=2.0, z=3.0))
    assert (twist.linear.x, twist.linear.y, twist.linear.z) == (1.0, 2.0, 3.0)
    assert twist.angular == Vector3()
    assert Point().x == 0.0 and isinstance(Point().x, float)
    assert Int32().data == 0
    header = Header()
    assert (header.stamp.sec, header.stamp.nanosec, header.frame_id) == (0, 0, '')
    # an int is accepted for a float field and stored as float
    p = Point(x=1)
    assert p.x == 1.0 and type(p.x) is float


def test_defaults_are_not_shared_between_instances():
    a, b = Twist(), Twist()
    a.linear.x = 5.0
    assert b.linear.x == 0.0
    s1, s2 = LaserScan(), LaserScan()
    assert s1.ranges is not s2.ranges
    c1, c2 = PoseWithCovariance(), PoseWithCovariance()
    c1.covariance[0] = 1.0
    assert c2.covariance[0] == 0.0


def test_unknown_keyword_names_the_field():
    with pytest.raises(MessageTypeError, match=r"std_msgs/msg/String has no field\(s\) 'dta'.*fields are: data"):
        String(dta='x')
    with pytest.raises(TypeError):  # MessageTypeError is a TypeError, as rclpy raises
        String(dta='x')


def test_equality():
    assert String(data='a') == String(data='a')
    assert String(data='a') != String(data='b')
    assert String(data='a') != Int32(data=1)
    assert String() != 'a'
    assert Twist(linear=Vector3(x=1.0)) == Twist(linear=Vector3(x=1.0))
    assert Twist(linear=Vector3(x=1.0)) != Twist(angular=Vector3(x=1.0))
    assert LaserScan(ranges=[1.0, 2.0]) == LaserScan(ranges=np.array([1.0, 2.0], np.float32))
    assert LaserScan(ranges=[1.0, 2.0]) != LaserScan(ranges=[1.0])
    with pytest.raises(TypeError):
        hash(String())  # mutable, like rclpy messages


def test_no_attributes_besides_fields():
    with pytest.raises(AttributeError):
        String().dta = 'x'  # a typo is an error, not a silently ignored attribute


def test_repr_like_rclpy():
    assert repr(String(data='x')) == "std_msgs.msg.String(data='x')"
    assert repr(Int32(data=3)) == 'std_msgs.msg.Int32(data=3)'
    assert repr(Vector3(x=1.0)) == 'geometry_msgs.msg.Vector3(x=1.0, y=0.0, z=0.0)'
    assert repr(Twist()) == ('geometry_msgs.msg.Twist(linear=geometry_msgs.msg.Vector3(x=0.0, y=0.0, z=0.0), '
                             'angular=geometry_msgs.msg.Vector3(x=0.0, y=0.0, z=0.0))')
    # rclpy shows a numeric sequence (an array.array) as a list, a fixed array as numpy does
    assert 'ranges=[1.0, 2.0], intensities=[])' in repr(LaserScan(ranges=[1.0, 2.0]))
    assert 'covariance=array([0., 0.,' in repr(PoseWithCovariance())
    assert repr(Image(data=b'\x01').data) == "array('B', [1])"


def test_introspection():
    assert String.get_fields_and_field_types() == {'data': 'string'}
    assert Twist.get_fields_and_field_types() == {'linear': 'geometry_msgs/Vector3',
                                                  'angular': 'geometry_msgs/Vector3'}
    assert String._TYPE == 'std_msgs/msg/String'
    assert len(String._HASH) == 16 and String._HASH != Int32._HASH


def test_copy_and_deepcopy_are_independent():
    original = Pose()
    original.position.x = 1.0
    for clone in (copy.copy(original), copy.deepcopy(original)):
        assert clone == original and clone is not original
        clone.position.x = 2.0
        assert original.position.x == 1.0


# -- type checks -------------------------------------------------------------------------------
@pytest.mark.parametrize('make, pattern', [
    (lambda: String(data=5), r'std_msgs/msg/String\.data must be a str'),
    (lambda: String(data=b'x'), r'std_msgs/msg/String\.data must be a str'),
    (lambda: Int32(data='1'), r'std_msgs/msg/Int32\.data must be an int'),
    (lambda: Int32(data=1.0), r'std_msgs/msg/Int32\.data must be an int'),
    (lambda: Int32(data=True), r'std_msgs/msg/Int32\.data must be an int'),
    (lambda: Int32(data=2**31), r'std_msgs/msg/Int32\.data = 2147483648 is out of range for int32'),
    (lambda: Int32(data=-2**31 - 1), r'Int32\.data = -2147483649 is out of range'),
    (lambda: Point(x='1'), r'geometry_msgs/msg/Point\.x must be a float'),
    (lambda: Vector3(x=None), r'Vector3\.x must be a float'),
    (lambda: Twist(linear=Point()), r'geometry_msgs/msg/Twist\.linear must be a geometry_msgs/msg/Vector3'),
    (lambda: Twist(linear={'x': 1.0}), r'Twist\.linear must be a geometry_msgs/msg/Vector3'),
    (lambda: PoseWithCovariance(covariance=[0.0] * 35), r'covariance must have exactly 36 elements, got 35'),
    (lambda: LaserScan(ranges='abc'), r'LaserScan\.ranges must be a sequence of float32'),
    (lambda: LaserScan(ranges=[[1.0, 2.0]]), r'LaserScan\.ranges must be one-dimensional'),
    (lambda: LaserScan(ranges=np.zeros((2, 2))), r'LaserScan\.ranges must be one-dimensional'),
    (lambda: LaserScan(ranges=5), r'LaserScan\.ranges must be a sequence of float32'),
    (lambda: UInt8MultiArray(data=[256]), r'UInt8MultiArray\.data has values out of range for uint8'),
    (lambda: UInt8MultiArray(data=[-1]), r'UInt8MultiArray\.data has values out of range for uint8'),
    (lambda: UInt8MultiArray(data=[1.5]), r'UInt8MultiArray\.data must be a sequence of uint8'),
    (lambda: Image(height=-1), r'sensor_msgs/msg/Image\.height = -1 is out of range for uint32'),
])
def test_wrong_values_raise_naming_the_field(make, pattern):
    with pytest.raises(MessageTypeError, match=pattern):
        make()


def test_assignment_is_checked_and_failed_assignment_keeps_the_old_value():
    msg = Int32(data=1)
    with pytest.raises(MessageTypeError, match='Int32.data'):
        msg.data = 'x'
    assert msg.data == 1
    msg.data = np.int16(7)  # numpy scalars are numbers too
    assert msg.data == 7 and type(msg.data) is int


def test_float32_range():
    LaserScan(range_max=3.0e38)
    LaserScan(range_max=float('inf'))
    with pytest.raises(MessageTypeError, match='out of range for float32'):
        LaserScan(range_max=1e39)


def test_float_arrays_are_checked_like_float_scalars():
    """An array element is held to the same rules as a scalar of its type (as in rclpy)."""
    assert LaserScan(ranges=[float('inf'), -3.0e38, 1]).ranges.tolist()[1:] == [pytest.approx(-3.0e38), 1.0]
    assert LaserScan(ranges=array.array('d', [1e30])).ranges.tolist() == [pytest.approx(1e30)]
    with pytest.raises(MessageTypeError, match=r'LaserScan\.ranges.*float32'):
        LaserScan(ranges=[1.0, 1e39])
    with pytest.raises(MessageTypeError, match=r'LaserScan\.ranges.*float32'):
        LaserScan(ranges=np.array([-1e39]))
    with pytest.raises(MessageTypeError, match=r'LaserScan\.ranges must be a sequence of float32'):
        LaserScan(ranges=['1.0'])
    with pytest.raises(MessageTypeError, match=r'PoseWithCovariance\.covariance must be a sequence of float64'):
        PoseWithCovariance(covariance=['0'] * 36)
    with pytest.raises(MessageTypeError, match=r'LaserScan\.ranges must be a sequence of float32'):
        LaserScan(ranges=[True, False])


def test_64_bit_arrays_take_every_int_of_their_range():
    """numpy turns [0, 2**63] into float64 (no one int type holds both), which lost precision or
    refused a valid uint64[] (found by tests/unit/test_round_trips.py)."""
    from interfaces.std_msgs.msg import Int64MultiArray, UInt64MultiArray
    assert list(UInt64MultiArray(data=[0, 2**63, 2**64 - 1]).data) == [0, 2**63, 2**64 - 1]
    assert list(Int64MultiArray(data=(-2**63, 2**62 + 1)).data) == [-2**63, 2**62 + 1]
    with pytest.raises(MessageTypeError, match=r'UInt64MultiArray\.data has values out of range for uint64'):
        UInt64MultiArray(data=[0, 2**64])
    with pytest.raises(MessageTypeError, match=r'UInt64MultiArray\.data has values out of range for uint64'):
        UInt64MultiArray(data=[-1, 2**63])
    with pytest.raises(MessageTypeError, match=r'Int64MultiArray\.data has values out of range for int64'):
        Int64MultiArray(data=[-1, 2**63])


# -- arrays as rclpy has them -------------------------------------------------------------------
def test_numeric_sequences_are_array_array():
    scan = LaserScan(ranges=[1.0, 2.5, 3.0])
    assert type(scan.ranges) is array.array and scan.ranges.typecode == 'f'
    assert scan.ranges.tolist() == [1.0, 2.5, 3.0]
    assert list(scan.ranges) == [1.0, 2.5, 3.0] and type(scan.ranges[0]) is float
    assert len(LaserScan().ranges) == 0
    scan.ranges.append(4.0)  # appendable and extendable, as in rclpy
    scan.ranges.extend([5.0])
    assert scan.ranges.tolist() == [1.0, 2.5, 3.0, 4.0, 5.0]
    given = array.array('f', [7.0])
    scan.ranges = given
    assert scan.ranges is given  # an array.array of the right typecode is kept, as rclpy does
    codes = {'int8[]': 'b', 'uint8[]': 'B', 'int16[]': 'h', 'uint16[]': 'H', 'int32[]': 'i', 'uint32[]': 'I',
             'int64[]': 'q', 'uint64[]': 'Q', 'float32[]': 'f', 'float64[]': 'd'}
    from interfaces.std_msgs import msg as std
    for name in ('Int8', 'UInt8', 'Int16', 'UInt16', 'Int32', 'UInt32', 'Int64', 'UInt64', 'Float32', 'Float64'):
        cls = getattr(std, name + 'MultiArray')
        assert cls().data.typecode == codes[cls._FIELD_TYPES['data']], name


def test_sequence_assignment_converts_lists_tuples_numpy_and_arrays():
    for value in ([1.0, 2.0], (1.0, 2.0), np.array([1.0, 2.0]), np.array([1.0, 2.0], np.float32),
                  array.array('d', [1.0, 2.0]), array.array('i', [1, 2]), np.array([1, 2]), range(1, 3)):
        scan = LaserScan(ranges=value)
        assert type(scan.ranges) is array.array and scan.ranges.typecode == 'f'
        assert scan.ranges.tolist() == [1.0, 2.0], value
    big = np.linspace(0, 1, 100_000, dtype=np.float32)
    assert np.array_equal(np.asarray(LaserScan(ranges=big).ranges), big)


def test_np_asarray_of_a_sequence_shares_its_buffer():
    """`np.asarray(msg.ranges)` is a view through the buffer protocol, not an element copy."""
    scan = LaserScan(ranges=[1.0, 2.0])
    view = np.asarray(scan.ranges)
    assert view.dtype == np.float32
    view[0] = 9.0
    assert scan.ranges[0] == 9.0


def test_fixed_numeric_arrays_are_numpy():
    pose = PoseWithCovariance()
    assert type(pose.covariance) is np.ndarray
    assert pose.covariance.dtype == np.float64 and pose.covariance.shape == (36,)
    given = np.arange(36, dtype=np.float64)
    pose.covariance = given
    assert pose.covariance is given  # kept as given, as rclpy does
    pose.covariance = list(range(36))
    assert pose.covariance.dtype == np.float64 and pose.covariance[35] == 35.0
    pose.covariance[0] = 5.0  # writable
    assert pose.covariance[0] == 5.0


def test_uint8_sequences_and_bytes():
    image = Image(data=b'\x00\x01\xff')
    assert type(image.data) is array.array and image.data.typecode == 'B'
    assert image.data.tolist() == [0, 1, 255]
    assert Image(data=bytearray(b'ab')).data.tolist() == [97, 98]
    assert Image(data=memoryview(b'ab')).data.tolist() == [97, 98]
    assert Image(data=[1, 2, 3]).data.tolist() == [1, 2, 3]
    assert Image(data=np.array([4, 5], dtype=np.uint8)).data.tolist() == [4, 5]
    image.data.frombytes(b'\x07')  # what cv_bridge does
    assert image.data[-1] == 7


def test_byte_fields_are_bytes_as_in_rclpy():
    from interfaces.diagnostic_msgs.msg import DiagnosticStatus
    from interfaces.std_msgs.msg import Byte, ByteMultiArray
    assert DiagnosticStatus.ERROR == b'\x02'
    assert DiagnosticStatus().level == b'\x00'
    status = DiagnosticStatus(level=DiagnosticStatus.WARN)
    assert status.level == DiagnosticStatus.WARN
    assert Byte(data=3).data == b'\x03'  # an int 0-255 is taken as that byte
    with pytest.raises(MessageTypeError, match=r'Byte\.data = 256 is out of range for byte'):
        Byte(data=256)
    with pytest.raises(MessageTypeError, match=r'Byte\.data must be a bytes of length 1'):
        Byte(data=b'ab')
    array_msg = ByteMultiArray(data=[b'\x01', b'\x02'])
    assert array_msg.data == [b'\x01', b'\x02']
    assert ByteMultiArray(data=b'\x01\x02').data == [b'\x01', b'\x02']
    back = deserialize(serialize(array_msg), ByteMultiArray)
    assert back == array_msg and msgpack.unpackb(serialize(array_msg))[1] == b'\x01\x02'
    assert deserialize(serialize(status), DiagnosticStatus).level == b'\x01'


def test_numeric_array_wire_form_is_header_then_raw_little_endian_tail():
    scan = LaserScan(ranges=[1.0, 2.0], intensities=[3.0])
    payload = serialize(scan)
    unpacker = msgpack.Unpacker()
    unpacker.feed(payload)
    header = unpacker.unpack()
    assert header[8:] == [2, 1]  # element counts in the header
    assert payload[unpacker.tell():] == np.array([1.0, 2.0, 3.0], dtype='<f4').tobytes()
    back = deserialize(payload, LaserScan)
    assert back.ranges.typecode == 'f' and back.ranges.tolist() == [1.0, 2.0]
    assert back.intensities.tolist() == [3.0]


def test_large_array_round_trip():
    data = np.random.default_rng(1).integers(0, 256, 1_000_000, dtype=np.uint8)
    image = Image(height=1000, width=1000, encoding='mono8', step=1000, data=data)
    back = deserialize(serialize(image), Image)
    assert back == image
    assert np.array_equal(back.data, data)


# -- nested messages and arrays of messages ----------------------------------------------------
def test_nested_messages():
    pose = Pose()
    pose.position.x = 1.5
    pose.orientation.w = 1.0
    assert pose.position == Point(x=1.5)
    from interfaces.geometry_msgs.msg import PoseArray
    array = PoseArray(poses=[Pose(), pose])
    assert array.poses[1].position.x == 1.5
    with pytest.raises(MessageTypeError, match=r'PoseArray\.poses must be a geometry_msgs/msg/Pose'):
        PoseArray(poses=[Point()])
    back = deserialize(serialize(array), PoseArray)
    assert back == array and back.poses[1].orientation.w == 1.0


# -- services and actions ----------------------------------------------------------------------
def test_service_classes():
    from interfaces.std_srvs.srv import SetBool
    from interfaces.example_interfaces.srv import AddTwoInts
    assert SetBool._TYPE == 'std_srvs/srv/SetBool'
    request = SetBool.Request(data=True)
    assert request.data is True
    response = SetBool.Response(success=True, message='ok')
    assert repr(response) == "std_srvs.srv.SetBool_Response(success=True, message='ok')"
    assert AddTwoInts.Request(a=1, b=2).b == 2
    with pytest.raises(MessageTypeError, match=r'AddTwoInts_Request\.a must be an int'):
        AddTwoInts.Request(a='1')
    assert deserialize(serialize(AddTwoInts.Response(sum=3)), AddTwoInts.Response).sum == 3
    assert typesupport.get_type('example_interfaces/srv/AddTwoInts_Request') is AddTwoInts.Request


def test_action_classes():
    from interfaces.action_tutorials_interfaces.action import Fibonacci
    assert Fibonacci._TYPE == 'action_tutorials_interfaces/action/Fibonacci'
    goal = Fibonacci.Goal(order=5)
    assert goal.order == 5
    result = Fibonacci.Result(sequence=[0, 1, 1, 2])
    assert result.sequence == array.array('i', [0, 1, 1, 2])
    result.sequence.append(3)  # the canonical Fibonacci server appends to the sequence
    assert repr(result) == 'action_tutorials_interfaces.action.Fibonacci_Result(sequence=[0, 1, 1, 2, 3])'
    feedback = Fibonacci.Feedback(partial_sequence=[0, 1])
    assert deserialize(serialize(feedback), Fibonacci.Feedback) == feedback
    assert typesupport.get_type('action_tutorials_interfaces/action/Fibonacci_Goal') is Fibonacci.Goal
    assert repr(goal) == 'action_tutorials_interfaces.action.Fibonacci_Goal(order=5)'


def test_action_msgs_constants():
    from interfaces.action_msgs.msg import GoalStatus
    assert (GoalStatus.STATUS_UNKNOWN, GoalStatus.STATUS_SUCCEEDED, GoalStatus.STATUS_ABORTED) == (0, 4, 6)
    assert GoalStatus().status == 0


# -- codec round trip for every shipped type ------------------------------------------------
def _value_for(ftype: FieldType, depth: int = 0):
    """A non-default value of `ftype` (within its bounds), to exercise the codec."""
    def scalar(i: int):
        base = ftype.base
        if base == 'bool':
            return True
        if base in ('float32', 'float64'):
            return 1.5 + i
        if base in ('string', 'wstring'):
            text = f'é{i}✓ x'
            return text[:ftype.string_bound] if ftype.string_bound is not None else text
        if base == 'byte':
            return bytes([200 + i])
        if base in ('char', 'uint8'):
            return 200 + i
        if base == 'int8':
            return -100 - i
        if base.startswith('uint'):
            return 2 ** (int(base[4:]) - 1) + i
        if base.startswith('int'):
            return -(2 ** (int(base[3:]) - 1)) + i
        cls = typesupport.get_message(base)
        return _filled(cls, depth + 1)
    if not ftype.is_array:
        return scalar(0)
    size = ftype.array_size if ftype.array == 'fixed' else min(2, ftype.array_size or 2)
    return [scalar(i) for i in range(size)]


def _filled(cls, depth: int = 0):
    msg = cls()
    if depth > 4:
        return msg
    for field in cls._SPEC.fields:
        setattr(msg, field.name, _value_for(field.type, depth))
    return msg


def _all_message_classes():
    for name in typesupport.list_interfaces():
        cls = typesupport.get_type(name)
        if hasattr(cls, 'Request'):
            yield f'{name}.Request', cls.Request
            yield f'{name}.Response', cls.Response
        elif hasattr(cls, 'Goal'):
            yield f'{name}.Goal', cls.Goal
            yield f'{name}.Result', cls.Result
            yield f'{name}.Feedback', cls.Feedback
        else:
            yield name, cls


def test_every_shipped_interface_is_listed_and_loads():
    names = typesupport.list_interfaces()
    assert len(names) > 100
    for expected in ('std_msgs/msg/String', 'geometry_msgs/msg/Twist', 'sensor_msgs/msg/Image',
                     'nav_msgs/msg/Odometry', 'builtin_interfaces/msg/Time', 'std_srvs/srv/Trigger',
                     'rcl_interfaces/srv/SetParameters', 'turtlesim/srv/Spawn', 'tf2_msgs/msg/TFMessage',
                     'action_tutorials_interfaces/action/Fibonacci', 'diagnostic_msgs/msg/DiagnosticArray',
                     'visualization_msgs/msg/Marker', 'example_interfaces/srv/AddTwoInts'):
        assert expected in names


@pytest.mark.parametrize('kind', ['default', 'filled'])
def test_codec_round_trip_for_every_shipped_type(kind):
    count = 0
    for name, cls in _all_message_classes():
        msg = cls() if kind == 'default' else _filled(cls)
        data = serialize(msg)
        back = deserialize(data, cls)
        assert type(back) is cls, name
        assert back == msg, name
        assert serialize(back) == data, name
        # the plain msgpack package reads the header: an array of the field values
        unpacker = msgpack.Unpacker()
        unpacker.feed(data)
        assert len(unpacker.unpack()) == len(cls._FIELDS), name
        count += 1
    assert count > 150


def test_decoded_arrays_own_their_memory():
    """Decoded arrays are copies out of the payload: writable, and alive after it is gone."""
    payload = bytearray(serialize(PoseWithCovariance(covariance=[1.0] * 36)))
    scan_payload = bytearray(serialize(LaserScan(ranges=[1.0])))
    pose = deserialize(payload, PoseWithCovariance)
    scan = deserialize(scan_payload, LaserScan)
    payload[:] = bytes(len(payload))
    scan_payload[:] = bytes(len(scan_payload))
    del payload, scan_payload
    assert pose.covariance.tolist() == [1.0] * 36 and scan.ranges.tolist() == [1.0]
    pose.covariance[0] = 2.0
    scan.ranges[0] = 2.0


_TWIST = msgpack.packb([[0.0, 0.0, 0.0], [0.0, 0.0, 0.0]])


@pytest.mark.parametrize('payload, cls, reason', [
    (b'', String, 'Unpack|ends'),
    (b'garbage', String, 'expected an array|trailing'),
    (msgpack.packb([1, 2]), String, 'expected an array of its 1 field'),
    (msgpack.packb({'data': 'x'}), String, 'expected an array of its 1 field'),
    (msgpack.packb([42]), String, r'String\.data must be a str'),
    (msgpack.packb([[1]]), String, r'String\.data must be a str'),
    (msgpack.packb([float('nan')]), String, r'String\.data must be a str'),
    (msgpack.packb([b'bytes']), String, r'String\.data must be a str'),
    (msgpack.packb([msgpack.ExtType(5, b'x')]), String, r'String\.data must be a str'),
    (msgpack.packb(['x']) + b'!', String, 'trailing bytes'),
    (b'\x91\xa2\xff\xfe', String, 'UnicodeDecodeError|utf'),
    (msgpack.packb([2**31]), Int32, 'out of range for int32'),
    (msgpack.packb([True]), Int32, r'Int32\.data must be an int'),
    (msgpack.packb([1.0]), Int32, r'Int32\.data must be an int'),
    (msgpack.packb([[0.0, 0.0], [0.0, 0.0, 0.0]]), Twist, 'Vector3: expected an array of its 3 field'),
    (msgpack.packb([['x', 0.0, 0.0], [0.0, 0.0, 0.0]]), Twist, r'Vector3\.x must be a float'),
    (_TWIST + b'\x00', Twist, '1 bytes follow|trailing'),
    (msgpack.packb([[[0, 0], ''], 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1e39, 0, 0]), LaserScan, 'out of range for float32'),
    (msgpack.packb([[[0, 0], ''], 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 2, 0]) + b'\x00' * 7, LaserScan,
     'ends inside'),
    (msgpack.packb([[[0, 0], ''], 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, -1, 0]), LaserScan, 'element count'),
    (msgpack.packb([[[0, 0], ''], 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 2**60, 0]), LaserScan, 'ends inside'),
    (msgpack.packb([[[0, 0], ''], 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 'x', 0]), LaserScan, 'element count'),
    (msgpack.packb([[[0.0] * 3, [0.0] * 4], 35]) + b'\x00' * 280, PoseWithCovariance, 'exactly 36'),
    (msgpack.packb([[[0, 0], 'f'], -1, 0, '', 0, 0, 0]), Image, 'out of range for uint32'),
    (msgpack.packb([[[0, 0], 'f'], 1, 1, 'x', 0, 1, 2**40]), Image, 'ends inside'),
])
def test_deserialize_rejects_foreign_payloads(payload, cls, reason):
    """The decoder enforces the definition as assignment does, with a one-line reason."""
    with pytest.raises(DecodeError, match='not a valid') as info:
        deserialize(payload, cls)
    assert re.search(reason, str(info.value)), str(info.value)
    assert '\n' not in str(info.value)


def test_deserialize_accepts_what_assignment_accepts():
    """An int where a float is meant is a float, as `Point(x=1)` is; bounds as assignment."""
    assert deserialize(msgpack.packb([[1, 2, 3], [0.0, 0.0, 0.0]]), Twist).linear == Vector3(x=1.0, y=2.0, z=3.0)
    assert type(deserialize(msgpack.packb([[1, 2, 3], [0.0, 0.0, 0.0]]), Twist).linear.x) is float
    assert deserialize(msgpack.packb([float('inf')]), __import__('interfaces.std_msgs.msg', fromlist=['Float32'])
                       .Float32).data == float('inf')


@pytest.mark.parametrize('count', [0, 15, 16, 65535, 65536])
def test_packed_array_joins_packed_items_into_a_msgpack_array(count):
    from zros.message import packed_array
    items = [i % 300 for i in range(count)]
    assert packed_array([msgpack.packb(i) for i in items]) == msgpack.packb(items)


def test_bounded_containers_changed_in_place_are_checked_on_publish(custom_package):
    import importlib
    Custom = importlib.import_module(f'interfaces.{custom_package}.msg').Custom
    msg = Custom()
    msg.pair.append(3.0)  # now 3 elements in a float32[<=2]
    with pytest.raises(MessageTypeError, match=r'Custom\.pair may have at most 2 elements, got 3'):
        serialize(msg)
    msg = Custom()
    msg.tags.append(5)
    with pytest.raises(MessageTypeError, match=r'Custom\.tags must be a str'):
        serialize(msg)


# -- user interface packages (ZROS_INTERFACE_PATH) -----------------------------------------
CUSTOM_MSG = '''\
# A message of a user's own package.
int32 ANSWER=42
string GREETING="hello"
float64 PI=3.14159

int32 count 7
float64 ratio 1
string name "abc"
string<=5 short
int32[3] triple
float32[<=2] pair [1.0, 2.0]
uint8[] blob
bool flag true
string[] tags ["x", "y"]
geometry_msgs/Point where
Header header
'''


@pytest.fixture
def custom_package(tmp_path, monkeypatch):
    """A fresh package (unique name: classes are cached per process) with msg/Custom.msg and
    srv/Ask.srv on ZROS_INTERFACE_PATH (request it after `domain`, which clears that variable);
    yields the package name."""
    package = f'my_pkg_{next(_unique)}_{id(tmp_path) % 100000}'
    (tmp_path / package / 'msg').mkdir(parents=True)
    (tmp_path / package / 'srv').mkdir()
    (tmp_path / package / 'msg' / 'Custom.msg').write_text(CUSTOM_MSG)
    (tmp_path / package / 'srv' / 'Ask.srv').write_text('string question\n---\nCustom answer\n')
    monkeypatch.setenv('ZROS_INTERFACE_PATH', str(tmp_path))
    yield package
    for module in [m for m in sys.modules if m.startswith(f'interfaces.{package}')]:
        del sys.modules[module]


def test_custom_package_import(custom_package):
    import importlib
    module = importlib.import_module(f'interfaces.{custom_package}.msg')
    Custom = module.Custom
    assert Custom._TYPE == f'{custom_package}/msg/Custom'
    # constants
    assert (Custom.ANSWER, Custom.GREETING, Custom.PI) == (42, 'hello', 3.14159)
    # defaults from the IDL
    msg = Custom()
    assert (msg.count, msg.ratio, msg.name, msg.short, msg.flag) == (7, 1.0, 'abc', '', True)
    assert type(msg.ratio) is float
    assert msg.triple.tolist() == [0, 0, 0] and msg.triple.dtype == np.int32
    assert msg.pair == array.array('f', [1.0, 2.0])
    assert msg.blob == array.array('B') and Custom().pair is not Custom().pair
    assert msg.tags == ['x', 'y']
    assert msg.where == Point() and msg.header == Header()
    # a default list is not shared
    msg.tags.append('z')
    assert Custom().tags == ['x', 'y']
    # bounds and sizes
    with pytest.raises(MessageTypeError, match=r'Custom\.short is longer than its bound of 5'):
        msg.short = 'toolong'
    msg.short = 'five!'
    with pytest.raises(MessageTypeError, match=r'Custom\.triple must have exactly 3 elements, got 2'):
        msg.triple = [1, 2]
    with pytest.raises(MessageTypeError, match=r'Custom\.pair may have at most 2 elements, got 3'):
        msg.pair = [1.0, 2.0, 3.0]
    with pytest.raises(MessageTypeError, match=r'Custom\.tags must be a str'):
        msg.tags = [1]
    with pytest.raises(MessageTypeError, match=r'Custom\.flag must be a bool'):
        msg.flag = 1
    msg.blob = b'\x01\x02'
    msg.triple = [1, 2, 3]
    # the codec
    back = deserialize(serialize(msg), Custom)
    assert back == msg
    assert back.short == 'five!' and back.blob.tolist() == [1, 2] and back.tags == ['x', 'y', 'z']
    # the `from ... import` form of the porting story
    namespace = {}
    exec(f'from interfaces.{custom_package}.msg import Custom as C', namespace)
    assert namespace['C'] is Custom


def test_custom_service_uses_custom_message(custom_package):
    import importlib
    Ask = importlib.import_module(f'interfaces.{custom_package}.srv').Ask
    Custom = importlib.import_module(f'interfaces.{custom_package}.msg').Custom
    response = Ask.Response()
    assert type(response.answer) is Custom and response.answer.count == 7
    assert f'{custom_package}/srv/Ask' in typesupport.list_interfaces(custom_package)


def test_unknown_interface_import_fails_cleanly():
    with pytest.raises(ImportError):
        from interfaces.std_msgs.msg import NoSuchMessage  # noqa: F401
    with pytest.raises(ImportError):
        import interfaces.no_such_package_xyz.msg  # noqa: F401


# -- rclpy programs that rely on array.array ---------------------------------------------------


def test_a_registered_stand_in_is_converted_on_assignment_and_refused_when_added_in_place():
    from interfaces.rcl_interfaces.msg import Parameter as ParameterMsg
    from interfaces.rcl_interfaces.msg import ParameterEvent
    from zros.errors import MessageTypeError
    from zros.message import serialize
    from zros.parameter import Parameter
    event = ParameterEvent(new_parameters=[Parameter('rate', value=5)])
    assert type(event.new_parameters[0]) is ParameterMsg and event.new_parameters[0].value.integer_value == 5
    serialize(event)
    event.new_parameters.append(Parameter('late', value=1))   # no setter ran: no conversion
    with pytest.raises(MessageTypeError, match='new_parameters'):
        serialize(event)
