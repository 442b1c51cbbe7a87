"""Rotations and homogeneous transforms with ROS's `tf_transformations` names and conventions.

Quaternions are `[x, y, z, w]` (w last, as in geometry_msgs), matrices are 4x4 numpy arrays,
angles are radians. Euler angles take an `axes` string as the ROS package does: a first letter
`s` (static axes: each turn about a fixed axis of the parent frame) or `r` (rotating axes: each
turn about the axis as moved by the previous turns), then the three axes in the order the angles
are given. The default `'sxyz'` is roll about x, then pitch about y, then yaw about z, all fixed:

    q = quaternion_from_euler(roll, pitch, yaw)          # [x, y, z, w]
    roll, pitch, yaw = euler_from_quaternion([q.x, q.y, q.z, q.w])

Plain numpy; no zros session is involved.
"""
from __future__ import annotations

import math
from typing import Sequence

import numpy as np

__all__ = ['identity_matrix', 'translation_matrix', 'translation_from_matrix', 'rotation_matrix',
           'euler_matrix', 'euler_from_matrix', 'euler_from_quaternion', 'quaternion_from_euler',
           'quaternion_about_axis', 'quaternion_matrix', 'quaternion_from_matrix', 'quaternion_multiply',
           'quaternion_conjugate', 'quaternion_inverse', 'quaternion_real', 'quaternion_imag',
           'quaternion_slerp', 'random_quaternion', 'random_rotation_matrix', 'concatenate_matrices',
           'inverse_matrix', 'is_same_transform', 'unit_vector', 'vector_norm']

_EPS = np.finfo(float).eps * 4.0
_AXIS_INDEX = {'x': 0, 'y': 1, 'z': 2}


def _parse_axes(axes: str) -> tuple[bool, tuple[int, int, int]]:
    """('sxyz') -> (static?, (0, 1, 2)); ValueError names the accepted form."""
    if (not isinstance(axes, str) or len(axes) != 4 or axes[0] not in 'sr'
            or any(c not in _AXIS_INDEX for c in axes[1:]) or axes[1] == axes[2] or axes[2] == axes[3]):
        raise ValueError(f"axes must be 's' or 'r' and three axes with no axis twice in a row, "
                         f"like 'sxyz' or 'rzxz'; got {axes!r}")
    return axes[0] == 's', tuple(_AXIS_INDEX[c] for c in axes[1:])


def _parity(i: int, j: int) -> float:
    """+1 when i -> j is a cyclic step (x->y, y->z, z->x), else -1."""
    return 1.0 if (j - i) % 3 == 1 else -1.0


def _axis_quaternion(axis: int, angle: float) -> np.ndarray:
    q = np.zeros(4)
    q[axis] = math.sin(angle / 2.0)
    q[3] = math.cos(angle / 2.0)
    return q


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
    axis = unit_vector(np.asarray(direction, dtype=float)[:3])
    m = quaternion_matrix(np.append(axis * math.sin(angle / 2.0), math.cos(angle / 2.0)))
    if point is not None:
        p = np.asarray(point, dtype=float)[:3]
        m[:3, 3] = p - m[:3, :3] @ p
    return m


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
    static, (i, j, k) = _parse_axes(axes)
    qi, qj, qk = _axis_quaternion(i, ai), _axis_quaternion(j, aj), _axis_quaternion(k, ak)
    if static:  # fixed axes: the first turn is applied first, so it is the rightmost factor
        return quaternion_multiply(qk, quaternion_multiply(qj, qi))
    return quaternion_multiply(qi, quaternion_multiply(qj, qk))


def euler_matrix(ai: float, aj: float, ak: float, axes: str = 'sxyz') -> np.ndarray:
    return quaternion_matrix(quaternion_from_euler(ai, aj, ak, axes))


def euler_from_matrix(matrix: np.ndarray, axes: str = 'sxyz') -> tuple[float, float, float]:
    """The three angles (in the order `axes` names them) of the rotation in `matrix`."""
    static, (i, j, k) = _parse_axes(axes)
    r = np.asarray(matrix, dtype=float)[:3, :3]
    if static:  # R = R_k(ak) R_j(aj) R_i(ai): the rotating sequence k, j, i with the angles reversed
        c, b, a = _intrinsic_angles(r, k, j, i)
        return a, b, c
    return _intrinsic_angles(r, i, j, k)


def _intrinsic_angles(r: np.ndarray, i: int, j: int, k: int) -> tuple[float, float, float]:
    """(a, b, c) with R = R_i(a) R_j(b) R_k(c), turns about the moving axes i, j, k."""
    if i != k:  # Tait-Bryan: three different axes
        s = _parity(i, j)
        cos_b = math.hypot(r[i, i], r[i, j])
        b = math.atan2(s * r[i, k], cos_b)
        if cos_b > _EPS:
            return math.atan2(-s * r[j, k], r[k, k]), b, math.atan2(-s * r[i, j], r[i, i])
        return math.atan2(s * r[k, j], r[j, j]), b, 0.0  # gimbal lock: put all of the turn in a
    m = 3 - i - j  # proper Euler (i, j, i): m is the axis not named
    s = _parity(i, j)
    sin_b = math.hypot(r[i, j], r[i, m])
    b = math.atan2(sin_b, r[i, i])
    if sin_b > _EPS:
        return math.atan2(r[j, i], -s * r[m, i]), b, math.atan2(r[i, j], s * r[i, m])
    return math.atan2(s * r[m, j], r[j, j]), b, 0.0


def euler_from_quaternion(quaternion: Sequence[float], axes: str = 'sxyz') -> tuple[float, float, float]:
    """(roll, pitch, yaw) of [x, y, z, w] with the default axes."""
    return euler_from_matrix(quaternion_matrix(quaternion), axes)


# -- quaternions -----------------------------------------------------------------------------------
def quaternion_about_axis(angle: float, axis: Sequence[float]) -> np.ndarray:
    v = unit_vector(np.asarray(axis, dtype=float)[:3])
    return np.append(v * math.sin(angle / 2.0), math.cos(angle / 2.0))


def quaternion_matrix(quaternion: Sequence[float]) -> np.ndarray:
    """4x4 rotation matrix of [x, y, z, w] (normalised first; a zero quaternion gives identity)."""
    q = np.asarray(quaternion, dtype=float)[:4]
    n = float(q @ q)
    if n < _EPS:
        return np.identity(4)
    x, y, z, w = q * math.sqrt(2.0 / n)
    return np.array([[1.0 - y * y - z * z, x * y - z * w, x * z + y * w, 0.0],
                     [x * y + z * w, 1.0 - x * x - z * z, y * z - x * w, 0.0],
                     [x * z - y * w, y * z + x * w, 1.0 - x * x - y * y, 0.0],
                     [0.0, 0.0, 0.0, 1.0]])


def quaternion_from_matrix(matrix: np.ndarray) -> np.ndarray:
    """[x, y, z, w] of the rotation in a 3x3 or 4x4 matrix."""
    from zros.tf2_ros.transform_math import from_matrix
    m = np.identity(4)
    m[:3, :3] = np.asarray(matrix, dtype=float)[:3, :3]
    return np.array(from_matrix(m)[3:])


def quaternion_multiply(quaternion1: Sequence[float], quaternion0: Sequence[float]) -> np.ndarray:
    """quaternion1 * quaternion0: the rotation quaternion0 followed by quaternion1."""
    x1, y1, z1, w1 = quaternion1
    x0, y0, z0, w0 = quaternion0
    return np.array([w1 * x0 + x1 * w0 + y1 * z0 - z1 * y0,
                     w1 * y0 - x1 * z0 + y1 * w0 + z1 * x0,
                     w1 * z0 + x1 * y0 - y1 * x0 + z1 * w0,
                     w1 * w0 - x1 * x0 - y1 * y0 - z1 * z0], dtype=float)


def quaternion_conjugate(quaternion: Sequence[float]) -> np.ndarray:
    x, y, z, w = quaternion
    return np.array([-x, -y, -z, w], dtype=float)


def quaternion_inverse(quaternion: Sequence[float]) -> np.ndarray:
    q = np.asarray(quaternion, dtype=float)
    return quaternion_conjugate(q) / float(q @ q)


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
