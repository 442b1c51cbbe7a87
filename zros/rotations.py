"""Angles and rotations about z: wrapping, differences, yaw <-> quaternion, in one place.

A robot on the floor turns about z only, so most of zros needs just its yaw: the controllers,
AMCL, SLAM, the simulators, the map files and the views. These formulas used to be written
out in each of them; a sign or a half-angle slip in one copy is a robot that turns the wrong
way in one node only. Full 3D rotations (Euler angles, matrices, slerp) are
zros.tf_transformations, which delegates to transforms3d.

Conventions: angles in radians, counter-clockwise about +z; wrapped angles lie in [-pi, pi);
quaternions in ROS's order (x, y, z, w), as geometry_msgs/Quaternion. Each function takes a
Python float (and then uses `math`: yaw -> quaternion gives bit-for-bit what the copies it
replaced gave) or a numpy array of any shape (vectorised).
"""
from __future__ import annotations

import math
from typing import TypeVar

import numpy as np

__all__ = ['wrap_angle', 'angle_diff', 'yaw_from_quaternion', 'quaternion_from_yaw']

Angle = TypeVar('Angle', float, np.ndarray)

_TWO_PI = 2.0 * math.pi


def _is_scalar(value: object) -> bool:
    return isinstance(value, (int, float))


def wrap_angle(angle: Angle) -> Angle:
    """`angle` [rad] wrapped into [-pi, pi) (pi itself becomes -pi).

    An angle already in range comes back unchanged, bit for bit: `(a + pi) % 2pi - pi` alone
    moves it by rounding, and a caller that compares the result with its input (turtlesim
    re-setting a body's angle when it changed) would see a change every step.
    """
    if _is_scalar(angle):
        return angle if -math.pi <= angle < math.pi else (angle + math.pi) % _TWO_PI - math.pi
    angle = np.asarray(angle, dtype=np.float64)
    return np.where((angle >= -math.pi) & (angle < math.pi), angle, (angle + math.pi) % _TWO_PI - math.pi)


def angle_diff(a: Angle, b: Angle) -> Angle:
    """The signed smallest turn from `b` to `a` [rad], in [-pi, pi): wrap_angle(a - b)."""
    if not (_is_scalar(a) and _is_scalar(b)):
        a, b = np.asarray(a, dtype=np.float64), np.asarray(b, dtype=np.float64)
    return wrap_angle(a - b)


def yaw_from_quaternion(x: Angle, y: Angle, z: Angle, w: Angle) -> Angle:
    """Yaw [rad] in [-pi, pi] of the quaternion (x, y, z, w): the heading its rotation gives +x.

    The quaternion need not be normalised (a goal often sets only w), and the all-zero one
    gives 0: the formula is scale-free, atan2(2 (wz + xy), w² + x² - y² - z²).
    """
    if all(_is_scalar(v) for v in (x, y, z, w)):
        return math.atan2(2.0 * (w * z + x * y), w * w + x * x - y * y - z * z)
    x, y, z, w = (np.asarray(v, dtype=np.float64) for v in (x, y, z, w))
    return np.arctan2(2.0 * (w * z + x * y), w * w + x * x - y * y - z * z)


def quaternion_from_yaw(yaw: Angle) -> tuple[Angle, Angle, Angle, Angle]:
    """(x, y, z, w) of the rotation by `yaw` [rad] about +z; for an array, four arrays of its
    shape (``np.stack(quaternion_from_yaw(yaws), axis=-1)`` gives (..., 4))."""
    if _is_scalar(yaw):
        return 0.0, 0.0, math.sin(yaw / 2.0), math.cos(yaw / 2.0)
    half = np.asarray(yaw, dtype=np.float64) / 2.0
    zeros = np.zeros_like(half)
    return zeros, zeros.copy(), np.sin(half), np.cos(half)
