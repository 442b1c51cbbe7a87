"""Poses in the plane (SE(2)) as numpy arrays, for the SLAM modules.

A pose is `(x [m], y [m], yaw [rad])`, the frame of a robot (or a scan, a node) expressed in
another frame; arrays of poses have shape (..., 3) and every function broadcasts over the
leading axes. `compose(a, b)` is "b expressed in a's frame, taken into a's parent frame", so
`compose(map_T_odom, odom_T_base)` is `map_T_base`, as with TF.
"""
from __future__ import annotations

import math

import numpy as np

from zros.rotations import wrap_angle

__all__ = ['compose', 'inverse', 'relative', 'transform_points', 'as_pose']


def as_pose(pose: object) -> np.ndarray:
    """A (3,) float64 array from any (x, y, yaw) sequence."""
    array = np.asarray(pose, dtype=np.float64)
    if array.shape[-1:] != (3,):
        raise ValueError(f'a pose is (x, y, yaw), got shape {array.shape}')
    return array


def compose(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """a ∘ b: pose b (given in frame a) in a's parent frame. Shapes (..., 3), broadcast."""
    a, b = np.asarray(a, dtype=np.float64), np.asarray(b, dtype=np.float64)
    c, s = np.cos(a[..., 2]), np.sin(a[..., 2])
    return np.stack([a[..., 0] + c * b[..., 0] - s * b[..., 1],
                     a[..., 1] + s * b[..., 0] + c * b[..., 1],
                     wrap_angle(a[..., 2] + b[..., 2])], axis=-1)


def inverse(a: np.ndarray) -> np.ndarray:
    """a⁻¹, so that compose(a, inverse(a)) is the identity."""
    a = np.asarray(a, dtype=np.float64)
    c, s = np.cos(a[..., 2]), np.sin(a[..., 2])
    return np.stack([-c * a[..., 0] - s * a[..., 1], s * a[..., 0] - c * a[..., 1], wrap_angle(-a[..., 2])], axis=-1)


def relative(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """a⁻¹ ∘ b: pose b seen from pose a (both in the same frame)."""
    a, b = np.asarray(a, dtype=np.float64), np.asarray(b, dtype=np.float64)
    c, s = np.cos(a[..., 2]), np.sin(a[..., 2])
    dx, dy = b[..., 0] - a[..., 0], b[..., 1] - a[..., 1]
    return np.stack([c * dx + s * dy, -s * dx + c * dy, wrap_angle(b[..., 2] - a[..., 2])], axis=-1)


def transform_points(pose: np.ndarray, points: np.ndarray) -> np.ndarray:
    """(N, 2) points given in `pose`'s frame, in the parent frame."""
    x, y, yaw = (float(v) for v in pose)
    c, s = math.cos(yaw), math.sin(yaw)
    points = np.asarray(points, dtype=np.float64)
    return points @ np.array([[c, s], [-s, c]]) + (x, y)
