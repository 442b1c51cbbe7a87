"""Rigid transforms as plain 7-tuples, for the TF buffer's hot path.

A transform is `(tx, ty, tz, qx, qy, qz, qw)`: the pose of a child frame in its parent, ROS's
quaternion order (w last). Applied to a point `p` given in the child frame it yields
`R(q) p + t` in the parent frame. Composition, inversion and interpolation of one transform
cost a few microseconds in plain Python floats, where the same on small numpy arrays costs
ten times more; the buffer does a handful per lookup. No Zenoh, no messages: unit-tested alone.
"""
from __future__ import annotations

import math

import numpy as np

__all__ = ['Transform', 'IDENTITY', 'compose', 'inverse', 'interpolate', 'slerp', 'rotate',
           'normalize_quaternion', 'QUATERNION_TOLERANCE', 'to_matrix', 'from_matrix']

Transform = tuple  # (tx, ty, tz, qx, qy, qz, qw), floats

IDENTITY: Transform = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0)

#: A quaternion whose squared norm is further than this from 1 is not just rounding noise.
QUATERNION_TOLERANCE = 1e-3

#: Above this cosine of the half-angle between two rotations, normalised linear interpolation
#: differs from slerp by less than 1e-9 rad, and avoids dividing by a tiny sine.
_SLERP_LINEAR_ABOVE = 0.9999


def compose(a: Transform, b: Transform) -> Transform:
    """a * b: `b` maps child->middle, `a` maps middle->parent; the result maps child->parent."""
    atx, aty, atz, ax, ay, az, aw = a
    btx, bty, btz, bx, by, bz, bw = b
    # rotate b's translation by a's rotation: v + 2w(u x v) + 2u x (u x v)
    cx = 2.0 * (ay * btz - az * bty)
    cy = 2.0 * (az * btx - ax * btz)
    cz = 2.0 * (ax * bty - ay * btx)
    return (atx + btx + aw * cx + (ay * cz - az * cy),
            aty + bty + aw * cy + (az * cx - ax * cz),
            atz + btz + aw * cz + (ax * cy - ay * cx),
            aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw,
            aw * bw - ax * bx - ay * by - az * bz)


def inverse(a: Transform) -> Transform:
    """The transform that undoes `a` (parent->child)."""
    tx, ty, tz, x, y, z, w = a
    # rotate -t by the conjugate (-x, -y, -z, w)
    cx = 2.0 * (-y * -tz + z * -ty)
    cy = 2.0 * (-z * -tx + x * -tz)
    cz = 2.0 * (-x * -ty + y * -tx)
    return (-tx + w * cx + (-y * cz + z * cy),
            -ty + w * cy + (-z * cx + x * cz),
            -tz + w * cz + (-x * cy + y * cx),
            -x, -y, -z, w)


def rotate(q: tuple, v: tuple) -> tuple:
    """Vector `v` (x, y, z) rotated by unit quaternion `q` (x, y, z, w)."""
    x, y, z, w = q
    vx, vy, vz = v
    cx = 2.0 * (y * vz - z * vy)
    cy = 2.0 * (z * vx - x * vz)
    cz = 2.0 * (x * vy - y * vx)
    return (vx + w * cx + (y * cz - z * cy),
            vy + w * cy + (z * cx - x * cz),
            vz + w * cz + (x * cy - y * cx))


def slerp(q0: tuple, q1: tuple, ratio: float) -> tuple:
    """Spherical linear interpolation of unit quaternions (x, y, z, w), along the shorter arc.

    ratio 0 gives q0, 1 gives q1 (or -q1, the same rotation)."""
    return interpolate((0.0, 0.0, 0.0, *q0), (0.0, 0.0, 0.0, *q1), ratio)[3:]


def interpolate(a: Transform, b: Transform, ratio: float) -> Transform:
    """Translation linear, rotation slerp; ratio 0 gives `a`, 1 gives `b` (tf2's rule).

    The slerp is written out here rather than calling `slerp`: this runs once per link of
    every lookup."""
    r0 = 1.0 - ratio
    x0, y0, z0, w0 = a[3], a[4], a[5], a[6]
    x1, y1, z1, w1 = b[3], b[4], b[5], b[6]
    dot = x0 * x1 + y0 * y1 + z0 * z1 + w0 * w1
    if dot < 0.0:
        x1, y1, z1, w1, dot = -x1, -y1, -z1, -w1, -dot
    if dot > _SLERP_LINEAR_ABOVE:
        s0, s1 = r0, ratio
    else:
        theta = math.acos(dot)
        sin_theta = math.sin(theta)
        s0 = math.sin(r0 * theta) / sin_theta
        s1 = math.sin(ratio * theta) / sin_theta
    x, y, z, w = s0 * x0 + s1 * x1, s0 * y0 + s1 * y1, s0 * z0 + s1 * z1, s0 * w0 + s1 * w1
    n = 1.0 / math.sqrt(x * x + y * y + z * z + w * w)
    return (a[0] * r0 + b[0] * ratio, a[1] * r0 + b[1] * ratio, a[2] * r0 + b[2] * ratio, x * n, y * n, z * n, w * n)


def normalize_quaternion(x: float, y: float, z: float, w: float) -> tuple[tuple, float]:
    """((x, y, z, w) scaled to unit length, squared norm it had). Raises ValueError for a zero
    or non-finite quaternion, which names no rotation at all."""
    n2 = x * x + y * y + z * z + w * w
    if not (n2 > 0.0 and math.isfinite(n2)):
        raise ValueError(f'quaternion ({x}, {y}, {z}, {w}) is not a rotation')
    if n2 == 1.0:
        return (x, y, z, w), n2
    n = math.sqrt(n2)
    return (x / n, y / n, z / n, w / n), n2


def to_matrix(a: Transform) -> np.ndarray:
    """4x4 homogeneous matrix of `a`."""
    tx, ty, tz, x, y, z, w = a
    m = np.eye(4)
    m[:3, :3] = [[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                 [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                 [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]]
    m[:3, 3] = (tx, ty, tz)
    return m


def from_matrix(m: np.ndarray) -> Transform:
    """The transform of a 4x4 homogeneous matrix whose upper-left block is a rotation."""
    r = np.asarray(m, dtype=float)
    trace = r[0, 0] + r[1, 1] + r[2, 2]
    # Pick the largest of w, x, y, z to divide by, for accuracy near 180-degree turns.
    if trace > 0.0:
        s = 2.0 * math.sqrt(trace + 1.0)
        w, x, y, z = 0.25 * s, (r[2, 1] - r[1, 2]) / s, (r[0, 2] - r[2, 0]) / s, (r[1, 0] - r[0, 1]) / s
    elif r[0, 0] > r[1, 1] and r[0, 0] > r[2, 2]:
        s = 2.0 * math.sqrt(1.0 + r[0, 0] - r[1, 1] - r[2, 2])
        w, x, y, z = (r[2, 1] - r[1, 2]) / s, 0.25 * s, (r[0, 1] + r[1, 0]) / s, (r[0, 2] + r[2, 0]) / s
    elif r[1, 1] > r[2, 2]:
        s = 2.0 * math.sqrt(1.0 + r[1, 1] - r[0, 0] - r[2, 2])
        w, x, y, z = (r[0, 2] - r[2, 0]) / s, (r[0, 1] + r[1, 0]) / s, 0.25 * s, (r[1, 2] + r[2, 1]) / s
    else:
        s = 2.0 * math.sqrt(1.0 + r[2, 2] - r[0, 0] - r[1, 1])
        w, x, y, z = (r[1, 0] - r[0, 1]) / s, (r[0, 2] + r[2, 0]) / s, (r[1, 2] + r[2, 1]) / s, 0.25 * s
    (x, y, z, w), _ = normalize_quaternion(float(x), float(y), float(z), float(w))
    return (float(r[0, 3]), float(r[1, 3]), float(r[2, 3]), x, y, z, w)
