"""Applying a TransformStamped to geometry_msgs types: tf2_geometry_msgs's role.

`Buffer.transform()` dispatches here by message type, and `zros.tf2_geometry_msgs` re-exports
the `do_transform_*` functions under tf2_geometry_msgs's names. Unlike upstream's, none of
them modifies the transform passed in. The result carries the transform's header (target
frame, lookup stamp), as upstream's does.
"""
from __future__ import annotations

import copy
from typing import Any, Callable

import numpy as np

from zros.tf2_ros.exceptions import TransformException
from zros.tf2_ros.transform_math import compose, rotate, to_matrix

__all__ = ['do_transform', 'do_transform_point', 'do_transform_vector3', 'do_transform_pose',
           'do_transform_pose_stamped', 'do_transform_pose_with_covariance_stamped',
           'do_transform_polygon_stamped', 'transform_covariance', 'transform_tuple']


def transform_tuple(transform: Any) -> tuple:
    """(tx, ty, tz, qx, qy, qz, qw) of a geometry_msgs TransformStamped or Transform."""
    t = getattr(transform, 'transform', transform)
    p, q = t.translation, t.rotation
    return (p.x, p.y, p.z, q.x, q.y, q.z, q.w)


def _header(transform: Any) -> Any:
    return copy.copy(transform.header)


def do_transform_point(point: Any, transform: Any) -> Any:
    """PointStamped into the transform's target frame."""
    from interfaces.geometry_msgs.msg import PointStamped
    t = transform_tuple(transform)
    x, y, z = rotate(t[3:], (point.point.x, point.point.y, point.point.z))
    result = PointStamped(header=_header(transform))
    result.point.x, result.point.y, result.point.z = x + t[0], y + t[1], z + t[2]
    return result


def do_transform_vector3(vector3: Any, transform: Any) -> Any:
    """Vector3Stamped rotated into the target frame (a direction: no translation)."""
    from interfaces.geometry_msgs.msg import Vector3Stamped
    t = transform_tuple(transform)
    result = Vector3Stamped(header=_header(transform))
    result.vector.x, result.vector.y, result.vector.z = rotate(t[3:], (vector3.vector.x, vector3.vector.y,
                                                                        vector3.vector.z))
    return result


def do_transform_pose(pose: Any, transform: Any) -> Any:
    """Pose (unstamped) into the target frame."""
    from interfaces.geometry_msgs.msg import Pose
    p, q = pose.position, pose.orientation
    tx, ty, tz, qx, qy, qz, qw = compose(transform_tuple(transform), (p.x, p.y, p.z, q.x, q.y, q.z, q.w))
    result = Pose()
    result.position.x, result.position.y, result.position.z = tx, ty, tz
    result.orientation.x, result.orientation.y, result.orientation.z, result.orientation.w = qx, qy, qz, qw
    return result


def do_transform_pose_stamped(pose: Any, transform: Any) -> Any:
    from interfaces.geometry_msgs.msg import PoseStamped
    return PoseStamped(header=_header(transform), pose=do_transform_pose(pose.pose, transform))


def transform_covariance(cov_in: Any, transform: Any) -> np.ndarray:
    """A 6x6 pose covariance (row-major, 36 values) rotated into the target frame: each 3x3
    block becomes R B R^T. Translation does not change a covariance."""
    rotation = to_matrix(transform_tuple(transform))[:3, :3]
    cov = np.asarray(cov_in, dtype=float).reshape(6, 6)
    big = np.zeros((6, 6))
    big[:3, :3] = big[3:, 3:] = rotation
    return (big @ cov @ big.T).reshape(36)


def do_transform_pose_with_covariance_stamped(pose: Any, transform: Any) -> Any:
    from interfaces.geometry_msgs.msg import PoseWithCovarianceStamped
    result = PoseWithCovarianceStamped(header=_header(transform))
    result.pose.pose = do_transform_pose(pose.pose.pose, transform)
    result.pose.covariance = transform_covariance(pose.pose.covariance, transform)
    return result


def do_transform_polygon_stamped(polygon: Any, transform: Any) -> Any:
    from interfaces.geometry_msgs.msg import Point32, PolygonStamped
    t = transform_tuple(transform)
    result = PolygonStamped(header=_header(transform))
    points = []
    for p in polygon.polygon.points:
        x, y, z = rotate(t[3:], (p.x, p.y, p.z))
        points.append(Point32(x=x + t[0], y=y + t[1], z=z + t[2]))
    result.polygon.points = points
    return result


_REGISTRY: dict[str, Callable[[Any, Any], Any]] = {
    'geometry_msgs/msg/PointStamped': do_transform_point,
    'geometry_msgs/msg/Vector3Stamped': do_transform_vector3,
    'geometry_msgs/msg/PoseStamped': do_transform_pose_stamped,
    'geometry_msgs/msg/PoseWithCovarianceStamped': do_transform_pose_with_covariance_stamped,
    'geometry_msgs/msg/PolygonStamped': do_transform_polygon_stamped,
}


def do_transform(obj: Any, transform: Any) -> Any:
    """Dispatch on the message type; TransformException for a type with no rule."""
    function = _REGISTRY.get(getattr(obj, '_TYPE', ''))
    if function is None:
        raise TransformException(
            f'Type {getattr(obj, "_TYPE", type(obj).__name__)} is not a transformable type '
            f'(supported: {", ".join(sorted(_REGISTRY))})')
    return function(obj, transform)
