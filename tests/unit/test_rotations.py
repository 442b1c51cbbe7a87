"""zros.rotations (the one home of yaw and angle helpers) and zros.tf_transformations' delegation
to transforms3d: pure, no processes. Property-based (hypothesis) for the round trips."""
from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from zros import tf_transformations as tft
from zros.rotations import angle_diff, quaternion_from_yaw, wrap_angle, yaw_from_quaternion

angles = st.floats(min_value=-1e4, max_value=1e4, allow_nan=False)
yaws = st.floats(min_value=-math.pi, max_value=math.pi, exclude_max=True)


@given(angle=angles)
def test_wrapping_lands_in_minus_pi_to_pi_on_the_same_direction(angle: float) -> None:
    wrapped = wrap_angle(angle)
    assert -math.pi <= wrapped < math.pi
    assert math.isclose(math.cos(wrapped), math.cos(angle), abs_tol=1e-9)
    assert math.isclose(math.sin(wrapped), math.sin(angle), abs_tol=1e-9)


@given(angle=st.floats(min_value=-math.pi, max_value=math.pi, exclude_max=True))
def test_an_angle_in_range_is_left_exactly_as_it_is(angle: float) -> None:
    assert wrap_angle(angle) == angle
    assert wrap_angle(np.array([angle]))[0] == angle


def test_wrapping_edges_and_types() -> None:
    assert wrap_angle(math.pi) == -math.pi and wrap_angle(-math.pi) == -math.pi
    assert wrap_angle(0.0) == 0.0 and isinstance(wrap_angle(1.0), float)
    wrapped = wrap_angle([3 * math.pi, -3 * math.pi, 0.5])                  # a list reads as an array
    assert isinstance(wrapped, np.ndarray) and np.allclose(wrapped, [-math.pi, -math.pi, 0.5])


@given(a=yaws, b=yaws)
def test_angle_diff_is_the_smallest_signed_turn(a: float, b: float) -> None:
    turn = angle_diff(a, b)
    assert -math.pi <= turn < math.pi
    assert math.isclose(math.cos(b + turn), math.cos(a), abs_tol=1e-9)             # b turned by it is a
    assert math.isclose(math.sin(b + turn), math.sin(a), abs_tol=1e-9)


@given(yaw=yaws, scale=st.floats(min_value=1e-3, max_value=1e3))
def test_yaw_and_quaternion_round_trip_at_any_scale(yaw: float, scale: float) -> None:
    x, y, z, w = quaternion_from_yaw(yaw)
    assert (x, y) == (0.0, 0.0) and math.isclose(z * z + w * w, 1.0)
    back = yaw_from_quaternion(x * scale, y * scale, z * scale, w * scale)
    assert math.isclose(math.cos(back), math.cos(yaw), abs_tol=1e-9)
    assert math.isclose(math.sin(back), math.sin(yaw), abs_tol=1e-9)


@given(yaw_array=arrays(np.float64, st.integers(1, 20), elements=yaws))
def test_arrays_give_what_each_element_gives(yaw_array: np.ndarray) -> None:
    q = np.stack(quaternion_from_yaw(yaw_array), axis=-1)
    assert q.shape == (len(yaw_array), 4)
    expected = np.array([quaternion_from_yaw(float(v)) for v in yaw_array])
    np.testing.assert_allclose(q, expected, atol=1e-15)
    np.testing.assert_allclose(yaw_from_quaternion(*q.T), [yaw_from_quaternion(*map(float, r)) for r in q], atol=1e-15)
    np.testing.assert_allclose(wrap_angle(yaw_array + 4 * math.pi), [wrap_angle(float(v) + 4 * math.pi) for v in yaw_array])


def test_yaw_of_the_quaternions_ros_users_write() -> None:
    assert yaw_from_quaternion(0.0, 0.0, 0.0, 0.0) == 0.0                     # all zero: no rotation
    assert yaw_from_quaternion(0.0, 0.0, 0.0, 1.0) == 0.0
    assert yaw_from_quaternion(0.0, 0.0, 1.0, 1.0) == pytest.approx(math.pi / 2)   # not normalised
    assert yaw_from_quaternion(0.0, 0.0, 1.0, 0.0) == pytest.approx(math.pi)
    # A full 3D rotation: the yaw of its sxyz Euler angles, as tf_transformations reads it.
    q = tft.quaternion_from_euler(0.2, -0.3, 1.1)
    assert yaw_from_quaternion(*q) == pytest.approx(tft.euler_from_quaternion(q)[2])


@given(yaw=yaws)
def test_tf_transformations_keeps_ros_order_over_transforms3d(yaw: float) -> None:
    q = tft.quaternion_from_euler(0.0, 0.0, yaw)
    np.testing.assert_allclose(q, quaternion_from_yaw(yaw), atol=1e-12)           # [x, y, z, w]
    matrix = tft.quaternion_matrix(q)
    np.testing.assert_allclose(matrix[:2, :2], [[math.cos(yaw), -math.sin(yaw)], [math.sin(yaw), math.cos(yaw)]],
                               atol=1e-12)
    back = tft.quaternion_from_matrix(matrix)
    assert back[3] >= 0.0 and np.allclose(np.abs(back @ q), 1.0)                  # the same rotation


def test_tf_transformations_quaternion_algebra() -> None:
    a, b = tft.quaternion_from_euler(0.1, 0.2, 0.3), tft.quaternion_about_axis(0.5, [0, 0, 2])
    np.testing.assert_allclose(b, quaternion_from_yaw(0.5), atol=1e-12)            # the axis is normalised
    np.testing.assert_allclose(tft.quaternion_conjugate(a), [-a[0], -a[1], -a[2], a[3]])
    np.testing.assert_allclose(tft.quaternion_multiply(a, tft.quaternion_inverse(a)), [0, 0, 0, 1], atol=1e-12)
    np.testing.assert_allclose(tft.quaternion_matrix([0, 0, 0, 0]), np.identity(4))
    turn = tft.rotation_matrix(math.pi / 2, [0, 0, 1], point=[1, 0, 0])             # about the line x = 1
    np.testing.assert_allclose(turn @ [2, 0, 0, 1], [1, 1, 0, 1], atol=1e-12)
    with pytest.raises(ValueError, match="like 'sxyz'"):
        tft.quaternion_from_euler(0, 0, 0, axes='sxxz')
