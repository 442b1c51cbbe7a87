"""Assisted teleoperation (Nav2's `assisted_teleop` behaviour), the arithmetic without ROS.

A person drives with `cmd_vel_teleop`; the behaviour projects the command forward from the
robot's pose in steps of `simulation_time_step` up to `projection_time` and, if a projected pose
is in collision, slows the command in proportion to how soon: by `t / projection_time` for a
collision at time t, to zero when the first step already collides. It never steers.
"""
from __future__ import annotations

import numpy as np

__all__ = ['projected_poses', 'collision_scale']


def projected_poses(pose: tuple[float, float, float], twist: tuple[float, float, float], step: float,
                    projection_time: float) -> tuple[np.ndarray, np.ndarray]:
    """(times (n,), poses (n, 3) as x, y, yaw) of the robot driving `twist` = (vx, vy, wz) in its
    own frame from `pose`, at t = step, 2 step, ... below `projection_time` (Nav2's steps)."""
    times = np.arange(1, max(int(np.ceil(projection_time / step - 1e-9)), 1)) * step
    if times.size == 0:
        times = np.array([step])
    x, y, yaw = pose
    vx, vy, wz = twist
    headings = yaw + wz * step * np.arange(times.size)           # the heading each step starts with
    dx = step * (vx * np.cos(headings) - vy * np.sin(headings))
    dy = step * (vx * np.sin(headings) + vy * np.cos(headings))
    poses = np.stack([x + np.cumsum(dx), y + np.cumsum(dy), headings + wz * step], axis=1)
    return times, poses


def collision_scale(times: np.ndarray, collides: np.ndarray, projection_time: float) -> float:
    """The factor for the teleop command: 1 when no projected pose collides, 0 when the first
    does, else the time of the first collision over `projection_time`."""
    hits = np.flatnonzero(collides)
    if hits.size == 0:
        return 1.0
    return 0.0 if hits[0] == 0 else float(times[hits[0]] / projection_time)
