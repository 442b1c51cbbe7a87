"""RViz's tools as plain functions: where a click lands on the ground, the pose a click-drag means,
and the messages the tools publish (2D Pose Estimate, Nav2 Goal, Publish Point, teleop).

2D Pose Estimate publishes geometry_msgs/PoseWithCovarianceStamped on /initialpose with RViz's
default covariance: 0.5 m standard deviation in x and y, pi/12 rad in yaw.
"""
from __future__ import annotations

import math
from typing import Any, NamedTuple

import numpy as np

from zros.view.scene.geometry import quat_from_yaw

__all__ = ['ground_point', 'drag_pose', 'PlanarPose', 'initial_pose', 'goal_pose', 'clicked_point', 'teleop_twist',
           'INITIAL_POSE_COVARIANCE', 'TELEOP_DIRECTIONS']

X_STD, Y_STD, YAW_STD = 0.5, 0.5, math.pi / 12.0
INITIAL_POSE_COVARIANCE = tuple(
    X_STD ** 2 if i == 0 else Y_STD ** 2 if i == 7 else YAW_STD ** 2 if i == 35 else 0.0 for i in range(36))
MIN_DRAG = 1e-3            # [m] a shorter drag keeps heading 0, as a plain click does in RViz

# direction -> (linear x sign, angular z sign)
TELEOP_DIRECTIONS = {'forward': (1, 0), 'back': (-1, 0), 'left': (0, 1), 'right': (0, -1),
                     'forward-left': (1, 1), 'forward-right': (1, -1), 'stop': (0, 0)}


class PlanarPose(NamedTuple):
    x: float      # [m]
    y: float      # [m]
    yaw: float    # [rad, -pi..pi, counter-clockwise from +x]


def ground_point(origin: Any, direction: Any, height: float = 0.0) -> np.ndarray | None:
    """Where the ray from `origin` along `direction` meets the plane z = `height` (in the fixed
    frame); None if it runs parallel to the plane or points away from it."""
    o = np.asarray(origin, dtype=np.float64)
    d = np.asarray(direction, dtype=np.float64)
    if abs(d[2]) < 1e-9:
        return None
    t = (height - o[2]) / d[2]
    if t <= 0:
        return None
    return o + t * d


def drag_pose(start: Any, end: Any) -> PlanarPose:
    """The pose a press at `start` dragged to `end` means: position at the press, heading
    towards the release."""
    sx, sy = float(start[0]), float(start[1])
    dx, dy = float(end[0]) - sx, float(end[1]) - sy
    yaw = math.atan2(dy, dx) if math.hypot(dx, dy) >= MIN_DRAG else 0.0
    return PlanarPose(sx, sy, yaw)


def _stamped(msg: Any, frame: str, stamp: Any) -> Any:
    msg.header.frame_id = frame
    if stamp is not None:
        msg.header.stamp = stamp
    return msg


def _fill_pose(target: Any, pose: PlanarPose) -> None:
    target.position.x, target.position.y, target.position.z = pose.x, pose.y, 0.0
    qx, qy, qz, qw = (float(v) for v in quat_from_yaw(pose.yaw))
    target.orientation.x, target.orientation.y, target.orientation.z, target.orientation.w = qx, qy, qz, qw


def initial_pose(pose: PlanarPose, frame: str, stamp: Any = None) -> Any:
    """The 2D Pose Estimate message (for /initialpose)."""
    from interfaces.geometry_msgs.msg import PoseWithCovarianceStamped
    msg = _stamped(PoseWithCovarianceStamped(), frame, stamp)
    _fill_pose(msg.pose.pose, pose)
    msg.pose.covariance = np.array(INITIAL_POSE_COVARIANCE, dtype=np.float64)
    return msg


def goal_pose(pose: PlanarPose, frame: str, stamp: Any = None) -> Any:
    """The Nav2 Goal message (for /goal_pose)."""
    from interfaces.geometry_msgs.msg import PoseStamped
    msg = _stamped(PoseStamped(), frame, stamp)
    _fill_pose(msg.pose, pose)
    return msg


def clicked_point(point: Any, frame: str, stamp: Any = None) -> Any:
    """The Publish Point message (for /clicked_point)."""
    from interfaces.geometry_msgs.msg import PointStamped
    msg = _stamped(PointStamped(), frame, stamp)
    msg.point.x, msg.point.y, msg.point.z = (float(v) for v in point[:3])
    return msg


def teleop_twist(direction: str, linear: float, angular: float) -> Any:
    """The geometry_msgs/Twist for a pad button at the given speeds [m/s, rad/s].

    Raises:
        ValueError: unknown direction.
    """
    from interfaces.geometry_msgs.msg import Twist
    try:
        forward, turn = TELEOP_DIRECTIONS[direction]
    except KeyError:
        raise ValueError(f"unknown teleop direction '{direction}'") from None
    msg = Twist()
    msg.linear.x = float(forward * linear)
    msg.angular.z = float(turn * angular)
    return msg
