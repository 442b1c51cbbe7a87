"""zros messages <-> rosbridge JSON (zros.bridges.message_json) and the protocol's pure parts:
ROS's JSON conventions (uint8[] as base64, time as {sec, nanosec}, NaN as null), defaults for
fields left out, "now" for times and header stamps, and errors that name the field."""
from __future__ import annotations

import json
import math

import pytest

from zros.bridges.message_json import message_from_json, message_to_json
from zros.bridges.rosbridge import encode_frame
from zros.bridges.websocket import ClientQueue
from zros.errors import MessageTypeError


def _now():
    from interfaces.builtin_interfaces.msg import Time
    return Time(sec=42, nanosec=7)


def test_binary_arrays_are_base64_and_round_trip() -> None:
    from interfaces.sensor_msgs.msg import Image
    image = Image(height=1, width=3, encoding='mono8', step=3, data=b'\x00\x7f\xff')
    data = message_to_json(image)
    assert data['data'] == 'AH//'
    assert data['header'] == {'stamp': {'sec': 0, 'nanosec': 0}, 'frame_id': ''}
    assert message_from_json(Image, json.loads(json.dumps(data)), now=_now) == image
    assert bytes(message_from_json(Image, {'data': [1, 2, 3]}, now=_now).data) == b'\x01\x02\x03'


def test_non_finite_floats_become_null_and_back_nan() -> None:
    from interfaces.sensor_msgs.msg import LaserScan
    scan = LaserScan(ranges=[1.5, math.inf, math.nan], range_max=math.inf)
    data = message_to_json(scan)
    assert data['ranges'] == [1.5, None, None] and data['range_max'] is None
    json.dumps(data, allow_nan=False)   # valid JSON for a browser's JSON.parse
    back = message_from_json(LaserScan, data, now=_now)
    assert back.ranges[0] == 1.5 and math.isnan(back.ranges[1]) and math.isnan(back.range_max)


def test_fields_left_out_keep_defaults_and_header_stamp_is_now() -> None:
    from interfaces.geometry_msgs.msg import PoseStamped, Twist
    goal = message_from_json(PoseStamped, {'header': {'frame_id': 'map'}, 'pose': {'position': {'x': 1}}}, now=_now)
    assert goal.header.frame_id == 'map' and (goal.header.stamp.sec, goal.header.stamp.nanosec) == (42, 7)
    assert goal.pose.position.x == 1.0 and goal.pose.orientation.w == 1.0
    assert message_from_json(PoseStamped, {}, now=_now).header.stamp.sec == 42
    assert message_from_json(PoseStamped, {'header': {'stamp': 'now'}}, now=_now).header.stamp.sec == 42
    given = message_from_json(PoseStamped, {'header': {'stamp': {'sec': 3, 'nanosec': 0}}}, now=_now)
    assert given.header.stamp.sec == 3
    assert message_from_json(Twist, None, now=_now) == Twist()


def test_nested_lists_and_bytes() -> None:
    from interfaces.std_msgs.msg import Byte
    from interfaces.visualization_msgs.msg import MarkerArray
    data = {'markers': [{'ns': 'a'}, {'ns': 'b', 'points': [{'x': 1.0}]}]}
    markers = message_from_json(MarkerArray, data, now=_now)
    assert [m.ns for m in markers.markers] == ['a', 'b'] and markers.markers[1].points[0].x == 1.0
    assert message_to_json(markers)['markers'][1]['points'][0] == {'x': 1.0, 'y': 0.0, 'z': 0.0}
    assert message_to_json(message_from_json(Byte, {'data': 200}, now=_now)) == {'data': 200}


@pytest.mark.parametrize('data, words', [
    ([1, 2], 'expected a JSON object'),
    ({'nope': 1}, "unknown field 'nope'"),
    ({'header': {'frame_id': 3}}, "'header.frame_id'"),
    ({'pose': {'position': {'x': 'far'}}}, "'pose.position.x'"),
    ({'pose': {'position': [1, 2]}}, "pose.position"),
])
def test_wrong_input_names_the_field(data, words) -> None:
    from interfaces.geometry_msgs.msg import PoseStamped
    with pytest.raises(MessageTypeError) as info:
        message_from_json(PoseStamped, data, now=_now)
    assert words in str(info.value)


def test_bad_base64_and_bad_byte() -> None:
    from interfaces.sensor_msgs.msg import Image
    from interfaces.std_msgs.msg import Byte
    with pytest.raises(MessageTypeError, match="'data' expects base64"):
        message_from_json(Image, {'data': '@@not base64@@'}, now=_now)
    with pytest.raises(MessageTypeError, match='byte'):
        message_from_json(Byte, {'data': 300}, now=_now)


def test_frames_are_json_or_cbor() -> None:
    import cbor2
    message = {'op': 'publish', 'topic': '/x', 'msg': {'data': 'AH//'}}
    assert json.loads(encode_frame(message)) == message
    assert cbor2.loads(encode_frame(message, 'cbor')) == message


def test_client_queue_drops_oldest_past_its_limits_and_counts() -> None:
    import asyncio
    loop = asyncio.new_event_loop()
    try:
        queue = ClientQueue(loop, limit=10)
        for i in range(5):
            queue.put(f'{i}abcd')        # 5 bytes each: two fit
        assert [queue.take(), queue.take(), queue.take()] == ['3abcd', '4abcd', None]
        assert queue.dropped == 3 and queue.size == 0
        queue.limit = 1000
        for i in range(4):
            queue.put(f'a{i}', 'topic:/a', 2)
            queue.put(f'b{i}', 'topic:/b', 0)
        assert [queue.take() for _ in range(6)] == ['b0', 'b1', 'a2', 'b2', 'a3', 'b3']
    finally:
        loop.close()
