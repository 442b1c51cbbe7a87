"""The TF math and frame tree without any transport: composition against 4x4 matrices,
interpolation (slerp) checked numerically, tf2's lookup rules and error messages, and
tf_transformations' conventions."""
from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

from zros import tf_transformations as tft
from zros.tf2_ros import (Buffer, ConnectivityException, ExtrapolationException, InvalidArgumentException,
                          LookupException, Time)
from zros.tf2_ros.buffer_core import BufferCore
from zros.tf2_ros.transform_math import compose, from_matrix, interpolate, inverse, slerp, to_matrix

RNG = np.random.default_rng(7)


def _random_transform() -> tuple:
    q = tft.random_quaternion(RNG.random(3))
    return (*RNG.uniform(-3, 3, 3).tolist(), *q.tolist())


def _yaw(yaw: float, x: float = 0.0, y: float = 0.0) -> tuple:
    return (x, y, 0.0, 0.0, 0.0, math.sin(yaw / 2), math.cos(yaw / 2))


def test_compose_and_inverse_agree_with_matrices():
    for _ in range(50):
        a, b = _random_transform(), _random_transform()
        np.testing.assert_allclose(to_matrix(compose(a, b)), to_matrix(a) @ to_matrix(b), atol=1e-12)
        np.testing.assert_allclose(to_matrix(inverse(a)), np.linalg.inv(to_matrix(a)), atol=1e-12)
        np.testing.assert_allclose(to_matrix(from_matrix(to_matrix(a))), to_matrix(a), atol=1e-12)


def test_slerp_moves_at_constant_angular_speed():
    q0, q1 = _yaw(0.0)[3:], _yaw(2.0)[3:]   # 2 rad apart: far outside the linear shortcut
    for ratio in (0.0, 0.1, 0.25, 0.5, 0.9, 1.0):
        q = slerp(q0, q1, ratio)
        assert 2 * math.atan2(q[2], q[3]) == pytest.approx(2.0 * ratio, abs=1e-12)
    # the shorter way round: from +170 deg to -170 deg passes through 180, not 0
    q = slerp(_yaw(math.radians(170))[3:], _yaw(math.radians(-170))[3:], 0.5)
    assert abs(2 * math.atan2(q[2], q[3])) == pytest.approx(math.pi, abs=1e-9)
    mid = interpolate(_yaw(0.0, 1.0, 2.0), _yaw(1.0, 3.0, 6.0), 0.25)
    assert mid[:2] == pytest.approx((1.5, 3.0))


def _chain_buffer() -> BufferCore:
    """map -> odom -> base_footprint (dynamic, 10 Hz from t=1 s) -> base_link -> base_scan (static)."""
    core = BufferCore()
    for k in range(50):
        t = 1_000_000_000 + k * 100_000_000
        core._insert('odom', 'map', t, _yaw(0.01 * k, 0.1 * k), 'test', False, 'w1')
        core._insert('base_footprint', 'odom', t, _yaw(0.05 * k, 0.2 * k), 'test', False, 'w1')
    core._insert('base_link', 'base_footprint', 0, (0.0, 0.0, 0.01, 0.0, 0.0, 0.0, 1.0), 'test', True, 'w2')
    core._insert('base_scan', 'base_link', 0, (-0.032, 0.0, 0.172, 0.0, 0.0, 0.0, 1.0), 'test', True, 'w2')
    return core


def _expected_scan_in_map(k: float) -> np.ndarray:
    """Same chain by matrices, with the dynamic links' parameters at (fractional) sample k."""
    m = to_matrix(_yaw(0.01 * k, 0.1 * k)) @ to_matrix(_yaw(0.05 * k, 0.2 * k))
    return m @ to_matrix((0.0, 0.0, 0.01, 0, 0, 0, 1.0)) @ to_matrix((-0.032, 0.0, 0.172, 0, 0, 0, 1.0))


def test_chain_lookup_latest_and_interpolated():
    core = _chain_buffer()
    latest = core.lookup_transform_core('map', 'base_scan', Time())
    assert (latest.header.frame_id, latest.child_frame_id) == ('map', 'base_scan')
    assert (latest.header.stamp.sec, latest.header.stamp.nanosec) == (5, 900_000_000)
    t = latest.transform
    got = to_matrix((t.translation.x, t.translation.y, t.translation.z,
                     t.rotation.x, t.rotation.y, t.rotation.z, t.rotation.w))
    np.testing.assert_allclose(got, _expected_scan_in_map(49), atol=1e-9)
    # halfway between samples 20 and 21 (and a quarter of the way 30 -> 31): linear in x and yaw
    for k in (20.5, 30.25):
        stamp = Time(nanoseconds=1_000_000_000 + int(k * 100_000_000))
        t = core.lookup_transform_core('map', 'base_scan', stamp).transform
        got = to_matrix((t.translation.x, t.translation.y, t.translation.z,
                         t.rotation.x, t.rotation.y, t.rotation.z, t.rotation.w))
        np.testing.assert_allclose(got, _expected_scan_in_map(k), atol=1e-9)
    # the inverse direction, and a lookup within the static part at a time no dynamic link covers
    back = core.lookup_transform_core('base_scan', 'map', Time(seconds=2.0)).transform
    assert back.translation.z == pytest.approx(-0.182)
    up = core.lookup_transform_core('base_link', 'base_scan', Time(seconds=100)).transform
    assert (up.translation.x, up.translation.z) == pytest.approx((-0.032, 0.172))


def test_lookup_errors_say_what_is_wrong():
    core = _chain_buffer()
    with pytest.raises(ExtrapolationException, match=r'extrapolation into the future\.  Requested time 7\.000000 '
                       r'but the latest data is at time 5\.900000, when looking up transform from frame '
                       r'\[base_scan\] to frame \[map\]'):
        core.lookup_transform_core('map', 'base_scan', Time(seconds=7))
    with pytest.raises(ExtrapolationException, match='into the past'):
        core.lookup_transform_core('map', 'base_scan', Time(seconds=0.5))
    with pytest.raises(LookupException, match=r'"nowhere" passed to lookupTransform argument source_frame does not '
                       r'exist\. Frames that exist: base_footprint, base_link, base_scan, map, odom\.'):
        core.lookup_transform_core('map', 'nowhere', Time())
    core._insert('island', 'sea', 0, _yaw(0.0), 'test', True, 'w3')
    with pytest.raises(ConnectivityException, match="between 'map' and 'island'"):
        core.lookup_transform_core('map', 'island', Time())
    with pytest.raises(InvalidArgumentException, match='cannot start with'):
        core.lookup_transform_core('/map', 'odom', Time())
    assert core.can_transform_core('map', 'base_scan', Time(seconds=3.0)) == (True, '')
    assert core.can_transform_core('map', 'base_scan', Time(seconds=9.0))[0] is False


def test_clear_after_a_jump_back_in_time_keeps_static_transforms():
    """tf2 clears only the dynamic caches: after /reset_simulation the latched /tf_static frames
    are not sent again, and a buffer that dropped them could never join map and base_link."""
    core = _chain_buffer()
    core.clear()
    assert not core.can_transform_core('odom', 'base_footprint', Time())[0]
    t = core.lookup_transform_core('base_footprint', 'base_scan', Time()).transform.translation
    assert (t.x, t.y, t.z) == pytest.approx((-0.032, 0.0, 0.182))
    assert 'base_footprint' in core.all_frames_as_string() and 'odom' not in core.all_frames_as_string()
    # New dynamic data after the jump (time restarted near 0) joins the static frames again.
    core._insert('base_footprint', 'odom', 5_000_000, _yaw(0.0, 1.0), 'test', False, 'w1')
    assert core.lookup_transform_core('odom', 'base_scan', Time()).transform.translation.x == pytest.approx(0.968)


def test_reparented_frame_and_cache_window():
    core = BufferCore()
    core._insert('robot', 'odom', 1_000_000_000, _yaw(0.0, 1.0), 'a', False, 'w')
    core._insert('robot', 'map', 2_000_000_000, _yaw(0.0, 5.0), 'a', False, 'w')
    core._insert('odom', 'map', 0, _yaw(0.0, 10.0), 'a', True, 'w')
    # at t=1 s the robot hung under odom (map x = 11), at 2 s directly under map (x = 5);
    # between the two samples the parent differs, so no interpolation: the earlier one holds
    for seconds, x in ((1.0, 11.0), (2.0, 5.0), (1.5, 11.0)):
        t = core.lookup_transform_core('map', 'robot', Time(seconds=seconds)).transform
        assert t.translation.x == pytest.approx(x)
    # samples older than the cache time (10 s) before the newest are dropped, and refused after
    core._insert('robot', 'map', 20_000_000_000, _yaw(0.0, 6.0), 'a', False, 'w')
    assert core._insert('robot', 'map', 3_000_000_000, _yaw(0.0, 6.0), 'a', False, 'w') is False
    with pytest.raises(ExtrapolationException):
        core.lookup_transform_core('map', 'robot', Time(seconds=2))


def test_bad_quaternions_are_normalised_once_or_refused(capfd):
    core = BufferCore()
    core._insert('a', 'b', 0, (0.0, 0.0, 0.0, 0.0, 0.0, 2.0, 2.0), 'x', True, 'w')
    core._insert('a', 'b', 0, (0.0, 0.0, 0.0, 0.0, 0.0, 3.0, 3.0), 'x', True, 'w')
    r = core.lookup_transform_core('b', 'a', Time()).transform.rotation
    assert (r.z, r.w) == pytest.approx((math.sqrt(0.5), math.sqrt(0.5)))
    err = capfd.readouterr().err
    assert err.count('TF_DENORMALIZED_QUATERNION') == 1, err
    with pytest.raises(InvalidArgumentException, match='not a rotation'):
        core._insert('c', 'b', 0, (0.0,) * 7, 'x', True, 'w')
    with pytest.raises(InvalidArgumentException, match='NaN'):
        core._insert('c', 'b', 0, (math.nan, 0, 0, 0, 0, 0, 1.0), 'x', True, 'w')


def test_two_writers_taking_turns_are_reported_once(capfd):
    core = BufferCore()
    for k in range(6):
        core._insert('base', 'odom' if k % 2 else 'map', 1_000_000_000 + k, _yaw(0.0), 'x', False, f'w{k % 2}')
    err = capfd.readouterr().err
    assert err.count('more than one broadcaster') == 1, err
    assert 'map, odom' in err
    # one writer replacing another (a restarted broadcaster) is not a fight
    calm = BufferCore()
    for k in range(6):
        calm._insert('base', 'odom', 1_000_000_000 + k, _yaw(0.0), 'x', False, 'old' if k < 3 else 'new')
    assert 'more than one broadcaster' not in capfd.readouterr().err


def test_buffer_waits_for_data_and_completes_futures():
    import threading
    buffer = Buffer()
    future = buffer.wait_for_transform_async('map', 'robot', Time())
    assert not future.done()
    assert buffer.can_transform('map', 'robot', Time(), timeout=0.05) is False
    timer = threading.Timer(0.1, buffer._insert_many, ([('robot', 'map', 5, _yaw(0.3))], 'x', False, 'w'))
    timer.start()
    assert buffer.can_transform('map', 'robot', Time(), timeout=5.0) is True
    assert future.done() and future.result() is True
    assert buffer.lookup_transform('map', 'robot', Time()).header.stamp.nanosec == 5


def test_transform_geometry_messages():
    from interfaces.geometry_msgs.msg import PointStamped, PoseStamped, PoseWithCovarianceStamped, Vector3Stamped
    buffer = Buffer()
    buffer._insert_many([('base_link', 'odom', 2_000_000_000, _yaw(math.pi / 2, 1.0, 2.0))], 'x', False, 'w')
    point = PointStamped()
    point.header.frame_id, point.header.stamp.sec = 'base_link', 2
    point.point.x = 1.0
    out = buffer.transform(point, 'odom')
    assert out.header.frame_id == 'odom'
    assert (out.point.x, out.point.y) == pytest.approx((1.0, 3.0))
    vec = Vector3Stamped()
    vec.header = point.header
    vec.vector.x = 1.0
    assert (buffer.transform(vec, 'odom').vector.y) == pytest.approx(1.0)
    pose = PoseStamped()
    pose.header = point.header
    pose.pose.orientation.w = 1.0
    out = buffer.transform(pose, 'odom')
    assert tft.euler_from_quaternion([out.pose.orientation.x, out.pose.orientation.y, out.pose.orientation.z,
                                      out.pose.orientation.w])[2] == pytest.approx(math.pi / 2)
    cov = PoseWithCovarianceStamped()
    cov.header = point.header
    cov.pose.pose.orientation.w = 1.0
    cov.pose.covariance = np.diag([4.0, 1.0, 0, 0, 0, 0]).reshape(36)
    out = buffer.transform(cov, 'odom')
    assert out.pose.covariance[0] == pytest.approx(1.0) and out.pose.covariance[7] == pytest.approx(4.0)


ALL_AXES = [f + ''.join(a) for f in 'sr' for a in itertools.product('xyz', repeat=3) if a[0] != a[1] != a[2]]


@pytest.mark.parametrize('axes', ALL_AXES)
def test_euler_round_trip_every_convention(axes):
    for _ in range(30):
        angles = RNG.uniform(-math.pi, math.pi, 3)
        matrix = tft.euler_matrix(*angles, axes=axes)
        again = tft.euler_matrix(*tft.euler_from_matrix(matrix, axes), axes=axes)
        np.testing.assert_allclose(again, matrix, atol=1e-9)


def test_tf_transformations_conventions():
    def rot(axis: int, a: float) -> np.ndarray:
        c, s = math.cos(a), math.sin(a)
        return [np.array([[1, 0, 0], [0, c, -s], [0, s, c]]), np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]]),
                np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])][axis]
    q = tft.quaternion_from_euler(0.1, 0.2, 0.3)         # roll, pitch, yaw -> [x, y, z, w]
    np.testing.assert_allclose(tft.quaternion_matrix(q)[:3, :3], rot(2, 0.3) @ rot(1, 0.2) @ rot(0, 0.1), atol=1e-12)
    assert tft.euler_from_quaternion(q) == pytest.approx((0.1, 0.2, 0.3))
    np.testing.assert_allclose(tft.quaternion_from_euler(0, 0, math.pi / 2), [0, 0, math.sqrt(0.5), math.sqrt(0.5)])
    a, b = tft.quaternion_from_euler(0, 0, 0.4), tft.quaternion_from_euler(0, 0, 0.5)
    assert tft.euler_from_quaternion(tft.quaternion_multiply(a, b))[2] == pytest.approx(0.9)
    np.testing.assert_allclose(tft.quaternion_multiply(a, tft.quaternion_inverse(a)), [0, 0, 0, 1], atol=1e-12)
    np.testing.assert_allclose(tft.quaternion_from_matrix(tft.quaternion_matrix(a)), a, atol=1e-12)
    m = tft.concatenate_matrices(tft.translation_matrix([1, 2, 3]), tft.euler_matrix(0, 0, math.pi / 2))
    np.testing.assert_allclose(m @ [1, 0, 0, 1], [1, 3, 3, 1], atol=1e-12)
    np.testing.assert_allclose(tft.translation_from_matrix(m), [1, 2, 3])
    assert tft.euler_from_quaternion(tft.quaternion_slerp(a, b, 0.5))[2] == pytest.approx(0.45)
    with pytest.raises(ValueError, match="like 'sxyz'"):
        tft.euler_matrix(0, 0, 0, axes='xyz')


def test_after_a_jump_back_data_from_before_it_is_dropped_until_the_clock_catches_up():
    """A reset simulation: the buffer is cleared, and a message stamped before the reset but
    delivered after it must not refill it with the future (tf2 would then refuse the new data)."""
    from zros.clock import ROSClock
    from zros.tf2_ros.buffer_core import BufferCore
    from zros.tf2_ros.listener_hub import _Target
    from zros.time import ClockType, Time
    clock = ROSClock()
    clock._set_ros_time_is_active(True)
    target = _Target(BufferCore(), clock, None)
    clock.set_ros_time_override(Time(seconds=47, clock_type=ClockType.ROS_TIME))
    assert target.check_clock() == 47_000_000_000
    clock.set_ros_time_override(Time(seconds=2, clock_type=ClockType.ROS_TIME))
    now = target.check_clock()
    old, new = [('odom', 'map', 47_500_000_000, ())], [('odom', 'map', 2_000_000_000, ())]
    assert target.stale(now, old) and not target.stale(now, new)
    clock.set_ros_time_override(Time(seconds=47, clock_type=ClockType.ROS_TIME))
    assert not target.stale(target.check_clock(), old)      # caught up: nothing is stale any more
