"""Rotations and homogeneous transforms with ROS's `tf_transformations` names and conventions.

Quaternions are `[x, y, z, w]` (w last, as in geometry_msgs), matrices are 4x4 numpy arrays,
angles are radians. Euler angles take an `axes` string as the ROS package does: a first letter
`s` (static axes: each turn about a fixed axis of the parent frame) or `r` (rotating axes: each
turn about the axis as moved by the previous turns), then the three axes in the order the angles
are given. The default `'sxyz'` is roll about x, then pitch about y, then yaw about z, all fixed:

    q = quaternion_from_euler(roll, pitch, yaw)          # [x, y, z, w]
    roll, pitch, yaw = euler_from_quaternion([q.x, q.y, q.z, q.w])

The rotation maths is transforms3d's, as in ROS's own tf_transformations (which wraps it too):
each function here only checks the `axes` string and turns transforms3d's (w, x, y, z)
quaternions into ROS's (x, y, z, w). transforms3d has no slerp, so that one is written here.
Plain numpy; no zros session is involved.
"""
from __future__ import annotations

import math
from typing import Sequence

import numpy as np
from transforms3d import axangles, euler, quaternions

__all__ = ['identity_matrix', 'translation_matrix', 'translation_from_matrix', 'rotation_matrix',
           'euler_matrix', 'euler_from_matrix', 'euler_from_quaternion', 'quaternion_from_euler',
           'quaternion_about_axis', 'quaternion_matrix', 'quaternion_from_matrix', 'quaternion_multiply',
           'quaternion_conjugate', 'quaternion_inverse', 'quaternion_real', 'quaternion_imag',
           'quaternion_slerp', 'random_quaternion', 'random_rotation_matrix', 'concatenate_matrices',
           'inverse_matrix', 'is_same_transform', 'unit_vector', 'vector_norm']

_EPS = np.finfo(float).eps * 4.0


def _check_axes(axes: str) -> str:
    """`axes` if it names one of the 24 conventions; else ValueError naming the accepted form
    (transforms3d would raise a bare KeyError)."""
    if (not isinstance(axes, str) or len(axes) != 4 or axes[0] not in 'sr'
            or any(c not in 'xyz' for c in axes[1:]) or axes[1] == axes[2] or axes[2] == axes[3]):
        raise ValueError(f"axes must be 's' or 'r' and three axes with no axis twice in a row, "
                         f"like 'sxyz' or 'rzxz'; got {axes!r}")
    return axes


def _wxyz(quaternion: Sequence[float]) -> np.ndarray:
    """transforms3d's order of a ROS (x, y, z, w) quaternion."""
    x, y, z, w = np.asarray(quaternion, dtype=float)[:4]
    return np.array([w, x, y, z])


def _xyzw(quaternion: np.ndarray) -> np.ndarray:
    """ROS's order of a transforms3d (w, x, y, z) quaternion."""
    w, x, y, z = quaternion
    return np.array([x, y, z, w], dtype=float)


def _homogeneous(rotation: np.ndarray) -> np.ndarray:
    m = np.identity(4)
    m[:3, :3] = rotation
    return m


# -- matrices ------------------------------------------------------------------------------------
def identity_matrix() -> np.ndarray:
    return np.identity(4)


def translation_matrix(direction: Sequence[float]) -> np.ndarray:
    m = np.identity(4)
    m[:3, 3] = np.asarray(direction, dtype=float)[:3]
    return m


def translation_from_matrix(matrix: np.ndarray) -> np.ndarray:
    return np.array(matrix, dtype=float, copy=True)[:3, 3]


def rotation_matrix(angle: float, direction: Sequence[float], point: Sequence[float] | None = None) -> np.ndarray:
    """Rotation by `angle` about the axis along `direction` through `point` (the origin by default)."""
    return axangles.axangle2aff(np.asarray(direction, dtype=float)[:3], angle,
                                None if point is None else np.asarray(point, dtype=float)[:3])


def concatenate_matrices(*matrices: np.ndarray) -> np.ndarray:
    """The product M0 @ M1 @ ... (applies the last matrix first)."""
    m = np.identity(4)
    for matrix in matrices:
        m = m @ np.asarray(matrix, dtype=float)
    return m


def inverse_matrix(matrix: np.ndarray) -> np.ndarray:
    return np.linalg.inv(matrix)


def is_same_transform(matrix0: np.ndarray, matrix1: np.ndarray) -> bool:
    """Whether two homogeneous matrices describe the same transform (up to their scale)."""
    m0 = np.array(matrix0, dtype=float)
    m1 = np.array(matrix1, dtype=float)
    return bool(np.allclose(m0 / m0[3, 3], m1 / m1[3, 3]))


# -- Euler angles ----------------------------------------------------------------------------------
def quaternion_from_euler(ai: float, aj: float, ak: float, axes: str = 'sxyz') -> np.ndarray:
    """[x, y, z, w] of three turns; with 'sxyz', ai=roll, aj=pitch, ak=yaw."""
    return _xyzw(euler.euler2quat(ai, aj, ak, _check_axes(axes)))


def euler_matrix(ai: float, aj: float, ak: float, axes: str = 'sxyz') -> np.ndarray:
    return _homogeneous(euler.euler2mat(ai, aj, ak, _check_axes(axes)))


def euler_from_matrix(matrix: np.ndarray, axes: str = 'sxyz') -> tuple[float, float, float]:
    """The three angles (in the order `axes` names them) of the rotation in `matrix`."""
    return euler.mat2euler(np.asarray(matrix, dtype=float)[:3, :3], _check_axes(axes))


def euler_from_quaternion(quaternion: Sequence[float], axes: str = 'sxyz') -> tuple[float, float, float]:
    """(roll, pitch, yaw) of [x, y, z, w] with the default axes."""
    return euler.quat2euler(_wxyz(quaternion), _check_axes(axes))


# -- quaternions -----------------------------------------------------------------------------------
def quaternion_about_axis(angle: float, axis: Sequence[float]) -> np.ndarray:
    return _xyzw(quaternions.axangle2quat(np.asarray(axis, dtype=float)[:3], angle))


def quaternion_matrix(quaternion: Sequence[float]) -> np.ndarray:
    """4x4 rotation matrix of [x, y, z, w] (normalised first; a zero quaternion gives identity)."""
    return _homogeneous(quaternions.quat2mat(_wxyz(quaternion)))


def quaternion_from_matrix(matrix: np.ndarray) -> np.ndarray:
    """[x, y, z, w] of the rotation in a 3x3 or 4x4 matrix (w >= 0)."""
    return _xyzw(quaternions.mat2quat(np.asarray(matrix, dtype=float)[:3, :3]))


def quaternion_multiply(quaternion1: Sequence[float], quaternion0: Sequence[float]) -> np.ndarray:
    """quaternion1 * quaternion0: the rotation quaternion0 followed by quaternion1."""
    return _xyzw(quaternions.qmult(_wxyz(quaternion1), _wxyz(quaternion0)))


def quaternion_conjugate(quaternion: Sequence[float]) -> np.ndarray:
    return _xyzw(quaternions.qconjugate(_wxyz(quaternion)))


def quaternion_inverse(quaternion: Sequence[float]) -> np.ndarray:
    return _xyzw(quaternions.qinverse(_wxyz(quaternion)))


def quaternion_real(quaternion: Sequence[float]) -> float:
    return float(quaternion[3])


def quaternion_imag(quaternion: Sequence[float]) -> np.ndarray:
    return np.array(quaternion[:3], dtype=float)


def quaternion_slerp(quat0: Sequence[float], quat1: Sequence[float], fraction: float, spin: int = 0,
                     shortestpath: bool = True) -> np.ndarray:
    """Spherical interpolation: fraction 0 gives quat0, 1 gives quat1; `spin` adds full turns."""
    q0 = unit_vector(np.asarray(quat0, dtype=float)[:4])
    q1 = unit_vector(np.asarray(quat1, dtype=float)[:4])
    if fraction == 0.0:
        return q0
    if fraction == 1.0:
        return q1
    d = float(q0 @ q1)
    if abs(abs(d) - 1.0) < _EPS:
        return q0
    if shortestpath and d < 0.0:
        d, q1 = -d, -q1
    angle = math.acos(max(-1.0, min(1.0, d))) + spin * math.pi
    if abs(angle) < _EPS:
        return q0
    inv_sin = 1.0 / math.sin(angle)
    return unit_vector(q0 * math.sin((1.0 - fraction) * angle) * inv_sin
                       + q1 * math.sin(fraction * angle) * inv_sin)


def random_quaternion(rand: Sequence[float] | None = None) -> np.ndarray:
    """A rotation drawn uniformly (from three numbers in [0, 1) when `rand` is given)."""
    u1, u2, u3 = np.random.random_sample(3) if rand is None else np.asarray(rand, dtype=float)[:3]
    a, b = math.sqrt(1.0 - u1), math.sqrt(u1)
    t1, t2 = 2.0 * math.pi * u2, 2.0 * math.pi * u3
    return np.array([math.sin(t1) * a, math.cos(t1) * a, math.sin(t2) * b, math.cos(t2) * b])


def random_rotation_matrix(rand: Sequence[float] | None = None) -> np.ndarray:
    return quaternion_matrix(random_quaternion(rand))


# -- vectors -------------------------------------------------------------------------------------
def vector_norm(data: Sequence[float], axis: int | None = None) -> float | np.ndarray:
    return np.linalg.norm(np.asarray(data, dtype=float), axis=axis)


def unit_vector(data: Sequence[float], axis: int | None = None) -> np.ndarray:
    v = np.array(data, dtype=float, copy=True)
    norm = np.linalg.norm(v, axis=axis, keepdims=axis is not None)
    return v / norm
