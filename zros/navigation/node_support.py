"""What the navigation nodes share: Nav2-named parameters, poses from TF, message helpers.

The nodes read their parameters by Nav2's names from whatever the parameter file gives them;
a name zros has no use for is listed once at start-up, at DEBUG (Nav2's files carry many: DWB
critics, behavior-tree plugin libraries, ...; at INFO they buried the lines that matter), never
an error.
"""
from __future__ import annotations

from typing import Any

import numpy as np

from zros.rotations import quaternion_from_yaw, yaw_from_quaternion
from zros.time import Time

__all__ = ['Nav2Params', 'yaw_of', 'quaternion_of', 'lookup_pose', 'pose_in_frame', 'path_msg', 'path_points',
           'duration_msg']


class Nav2Params:
    """Reads a node's parameters by Nav2's names, with Nav2's defaults, and remembers which it used."""

    def __init__(self, node: Any) -> None:
        self.node = node
        self.used: set[str] = {'use_sim_time'}

    def get(self, name: str, default: Any) -> Any:
        """The parameter's value converted to the default's type (a file's `1` for a float is 1.0)."""
        self.used.add(name)
        if self.node.has_parameter(name):
            value = self.node.get_parameter(name).value
        else:
            value = self.node._parameter_overrides.get(name, default)
            self.node.declare_parameter(name, _convert(value, default), ignore_override=True)
        return _convert(value, default)

    def unused(self) -> list[str]:
        return sorted(n for n in self.node._parameter_overrides if n not in self.used)

    def report_unused(self) -> None:
        names = self.unused()
        if names:
            self.node.get_logger().debug(
                f'Parameters zros does not use (ignored): {", ".join(names)}')


def _convert(value: Any, default: Any) -> Any:
    if value is None:
        return default
    if isinstance(default, bool):
        if isinstance(value, str):
            return value.strip().lower() in ('true', '1', 'yes')
        return bool(value)
    if isinstance(default, float) and isinstance(value, (int, float, str)) and not isinstance(value, bool):
        return float(value)
    if isinstance(default, int) and isinstance(value, (int, float, str)) and not isinstance(value, bool):
        return int(float(value))
    if isinstance(default, list) and isinstance(value, (list, tuple)):
        return list(value)
    if isinstance(default, str):
        return str(value)
    return value


def yaw_of(q: Any) -> float:
    """Yaw [rad] of a geometry_msgs Quaternion (need not be normalised: goals often set only w)."""
    return yaw_from_quaternion(q.x, q.y, q.z, q.w)


def quaternion_of(yaw: float, q: Any) -> Any:
    """Fill the Quaternion message `q` with a rotation of `yaw` [rad] about z; return it."""
    q.x, q.y, q.z, q.w = quaternion_from_yaw(yaw)
    return q


def lookup_pose(buffer: Any, target_frame: str, source_frame: str) -> tuple[float, float, float]:
    """(x, y, yaw) of `source_frame`'s origin in `target_frame`, latest transform; raises tf2's exceptions."""
    t = buffer.lookup_transform(target_frame, source_frame, Time()).transform
    return t.translation.x, t.translation.y, yaw_of(t.rotation)


def pose_in_frame(buffer: Any, pose: Any, frame: str) -> tuple[float, float, float]:
    """(x, y, yaw) of a PoseStamped in `frame` (2D, latest transform; an empty frame_id is taken
    as `frame`); raises tf2's exceptions."""
    p = pose.pose
    x, y, yaw = p.position.x, p.position.y, yaw_of(p.orientation)
    source = pose.header.frame_id or frame
    if source == frame:
        return x, y, yaw
    t = buffer.lookup_transform(frame, source, Time()).transform
    tyaw = yaw_of(t.rotation)
    c, s = np.cos(tyaw), np.sin(tyaw)
    return (float(t.translation.x + c * x - s * y), float(t.translation.y + s * x + c * y), tyaw + yaw)


def path_msg(points: np.ndarray, yaws: np.ndarray, frame_id: str, stamp: Any) -> Any:
    """nav_msgs/Path of (N, 2) points with headings."""
    from interfaces.geometry_msgs.msg import PoseStamped
    from interfaces.nav_msgs.msg import Path
    path = Path()
    path.header.frame_id = frame_id
    path.header.stamp = stamp
    poses = []
    for (x, y), yaw in zip(points.tolist(), yaws.tolist()):
        p = PoseStamped()
        p.header.frame_id = frame_id
        p.header.stamp = stamp
        p.pose.position.x, p.pose.position.y = x, y
        quaternion_of(yaw, p.pose.orientation)
        poses.append(p)
    path.poses = poses
    return path


def path_points(path: Any) -> tuple[np.ndarray, float]:
    """(N, 2) points of a nav_msgs/Path and its last pose's yaw."""
    pts = np.array([[p.pose.position.x, p.pose.position.y] for p in path.poses], np.float64).reshape(-1, 2)
    yaw = yaw_of(path.poses[-1].pose.orientation) if path.poses else 0.0
    return pts, yaw


def duration_msg(seconds: float) -> Any:
    from interfaces.builtin_interfaces.msg import Duration
    seconds = max(0.0, float(seconds))
    sec = int(seconds)
    return Duration(sec=sec, nanosec=int((seconds - sec) * 1e9))
