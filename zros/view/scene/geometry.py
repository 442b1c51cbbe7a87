"""Rigid transforms as numpy arrays, in ROS's conventions, for turning messages into scene data.

ROS writes quaternions x, y, z, w (`geometry_msgs/Quaternion`); viser wants w, x, y, z. Every
function here takes and returns ROS's order; `wxyz()` converts at the edge, where a scene node
is posed. Points are (N, 3) float arrays, rotated by vectorised quaternion algebra (no loop per
point).
"""
from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np

from zros.rotations import quaternion_from_yaw, yaw_from_quaternion

__all__ = ['Transform', 'IDENTITY', 'quat_multiply', 'quat_rotate', 'quat_from_yaw', 'yaw_of',
           'wxyz', 'pose_transform', 'transform_of_msg']


def quat_multiply(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Hamilton product a*b of xyzw quaternions ((4,) or (N, 4), broadcast)."""
    ax, ay, az, aw = np.moveaxis(np.asarray(a, dtype=np.float64), -1, 0)
    bx, by, bz, bw = np.moveaxis(np.asarray(b, dtype=np.float64), -1, 0)
    return np.stack([aw * bx + ax * bw + ay * bz - az * by,
                     aw * by - ax * bz + ay * bw + az * bx,
                     aw * bz + ax * by - ay * bx + az * bw,
                     aw * bw - ax * bx - ay * by - az * bz], axis=-1)


def quat_rotate(q: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Points (N, 3) rotated by the xyzw quaternion `q` ((4,) or (N, 4))."""
    q = np.asarray(q, dtype=np.float64)
    points = np.asarray(points, dtype=np.float64)
    u, w = q[..., :3], q[..., 3:4]
    t = 2.0 * np.cross(u, points)
    return points + w * t + np.cross(u, t)


def quat_from_yaw(yaw: float | np.ndarray) -> np.ndarray:
    """xyzw quaternion(s) of a rotation about +z by `yaw` [rad]: (4,) or (..., 4)."""
    return np.stack(quaternion_from_yaw(np.asarray(yaw, dtype=np.float64)), axis=-1)


def yaw_of(q: np.ndarray) -> float:
    """Heading [rad, -pi..pi, counter-clockwise from +x] of an xyzw quaternion."""
    return yaw_from_quaternion(*(float(v) for v in q))


def wxyz(q: np.ndarray) -> np.ndarray:
    """viser's order (w, x, y, z) of a ROS (x, y, z, w) quaternion ((4,) or (N, 4))."""
    q = np.asarray(q, dtype=np.float64)
    return np.concatenate([q[..., 3:4], q[..., :3]], axis=-1)


class Transform(NamedTuple):
    """Maps points from a child frame into its parent: p_parent = R p_child + t."""
    translation: np.ndarray   # (3,) [m]
    rotation: np.ndarray      # (4,) xyzw, unit

    def __matmul__(self, other: 'Transform') -> 'Transform':
        """self @ other: apply `other` first (parent<-child @ child<-grandchild)."""
        return Transform(self.translation + quat_rotate(self.rotation, other.translation[None])[0],
                         _normalized(quat_multiply(self.rotation, other.rotation)))

    def apply(self, points: np.ndarray) -> np.ndarray:
        """(N, 3) points in the child frame -> the same points in the parent frame."""
        return quat_rotate(self.rotation, points) + self.translation

    def inverse(self) -> 'Transform':
        conjugate = self.rotation * np.array([-1.0, -1.0, -1.0, 1.0])
        return Transform(-quat_rotate(conjugate, self.translation[None])[0], conjugate)

    @property
    def yaw(self) -> float:
        return yaw_of(self.rotation)


IDENTITY = Transform(np.zeros(3), np.array([0.0, 0.0, 0.0, 1.0]))


def _normalized(q: np.ndarray) -> np.ndarray:
    norm = float(np.linalg.norm(q))
    return q / norm if norm > 1e-12 else np.array([0.0, 0.0, 0.0, 1.0])


def pose_transform(pose: Any) -> Transform:
    """The Transform of a geometry_msgs/Pose (position + orientation)."""
    p, o = pose.position, pose.orientation
    return Transform(np.array([p.x, p.y, p.z], dtype=np.float64),
                     _normalized(np.array([o.x, o.y, o.z, o.w], dtype=np.float64)))


def transform_of_msg(transform: Any) -> Transform:
    """The Transform of a geometry_msgs/Transform (translation + rotation)."""
    t, r = transform.translation, transform.rotation
    return Transform(np.array([t.x, t.y, t.z], dtype=np.float64),
                     _normalized(np.array([r.x, r.y, r.z, r.w], dtype=np.float64)))
