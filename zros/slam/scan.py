"""A planar laser scan as points: what the mapper and the matcher take from a LaserScan.

Readings follow REP 117: a finite range within [range_min, range_max] is a return (an obstacle
there); +inf, or a range beyond the limits, means nothing was hit along the beam; -inf (too
close) and NaN (no measurement) tell nothing. Beams with no return still show free space: as
Cartographer's `missing_data_ray_length`, the ray is taken as free up to that length.
"""
from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from zros.slam.geometry import transform_points

__all__ = ['ScanPoints', 'scan_points', 'voxel_filter', 'within_reach']


class ScanPoints(NamedTuple):
    """One scan in the robot's base frame.

    origin: (2,) where the rays start (the sensor) [m].
    hits: (N, 2) float32 endpoints of the returns [m].
    misses: (M, 2) float32 ends of the free rays of beams with no return [m].
    """
    origin: np.ndarray
    hits: np.ndarray
    misses: np.ndarray


def scan_points(ranges: np.ndarray, angle_min: float, angle_increment: float, *, range_min: float,
                range_max: float, sensor_pose: tuple[float, float, float] = (0.0, 0.0, 0.0),
                max_range: float | None = None, missing_data_ray_length: float | None = None) -> ScanPoints:
    """Turn scan ranges into points in the base frame.

    Args:
        ranges: (K,) ranges [m] (any numeric sequence; LaserScan.ranges).
        angle_min, angle_increment: beam k points at `angle_min + k * angle_increment` [rad] in
            the sensor frame, counter-clockwise.
        range_min, range_max: the sensor's limits [m].
        sensor_pose: (x, y, yaw) of the sensor in the base frame.
        max_range: returns farther than this [m] are used as free rays only (None: range_max).
        missing_data_ray_length: free length [m] given to beams with no return (None: range_max;
            0: none).
    """
    r = np.asarray(ranges, dtype=np.float64)
    angles = angle_min + angle_increment * np.arange(len(r))
    limit = range_max if max_range is None else min(range_max, max_range)
    missing = range_max if missing_data_ray_length is None else missing_data_ray_length
    with np.errstate(invalid='ignore'):
        hit = np.isfinite(r) & (r >= range_min) & (r <= limit)
        no_return = (r == math.inf) | (np.isfinite(r) & (r > limit))
    free = np.where(np.isfinite(r) & (r > limit), np.minimum(r, missing), missing)
    hit_xy = np.stack([r[hit] * np.cos(angles[hit]), r[hit] * np.sin(angles[hit])], axis=1)
    keep = no_return & (missing > 0)
    miss_xy = np.stack([free[keep] * np.cos(angles[keep]), free[keep] * np.sin(angles[keep])], axis=1)
    pose = np.asarray(sensor_pose, dtype=np.float64)
    return ScanPoints(pose[:2].copy(), transform_points(pose, hit_xy).astype(np.float32),
                      transform_points(pose, miss_xy).astype(np.float32))


def voxel_filter(points: np.ndarray, size: float) -> np.ndarray:
    """One point per `size` [m] square: the mean of the points in it. Near the sensor a scan is
    dense and far away sparse; thinning it evens the weight each surface gets in matching."""
    if len(points) == 0:
        return np.asarray(points, dtype=np.float64).reshape(0, 2)
    keys = np.floor(np.asarray(points, dtype=np.float64) / size).astype(np.int64)
    _, inverse, counts = np.unique(keys, axis=0, return_inverse=True, return_counts=True)
    inverse = inverse.ravel()
    sums = np.zeros((len(counts), 2))
    np.add.at(sums, inverse, points)
    return sums / counts[:, None]


def within_reach(points: np.ndarray, origins: np.ndarray, reach: np.ndarray) -> np.ndarray:
    """(N,) bool: which of `points` (N, 2) lie within `reach` (K,) [m] of at least one of the
    sensor positions `origins` (K, 2), all in one frame.

    A local map made of K scans can only hold what those scans could reach. A new scan's points
    beyond that (a corridor's walls a step further on) fit nowhere on it whatever the pose, and
    score nothing: they pull the match back onto the mapped part instead of telling where the
    robot is, so the front end matches without them."""
    points = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    origins = np.asarray(origins, dtype=np.float64).reshape(-1, 2)
    distance = np.hypot(points[:, None, 0] - origins[None, :, 0], points[:, None, 1] - origins[None, :, 1])
    return np.any(distance <= np.asarray(reach, dtype=np.float64)[None, :], axis=1)
