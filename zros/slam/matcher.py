"""Scan-to-map matching: an exhaustive correlative search made fast by branch and bound over a
multi-resolution grid, then Gauss-Newton refinement below the cell size.

1. Correlative search (Olson 2009; Hess et al. 2016). Every rotation in the angular window (one
   step turns the farthest point by about one cell) and every whole-cell translation in the
   linear window is a candidate; its score is the mean likelihood of the scan's points placed
   there (zros.slam.match_grid). Translations are grouped in 2^k x 2^k blocks whose level-k
   score bounds every member's score from above. A greedy descent (best block, then its best
   quarter, ...) gives a first real score; then, level by level, only blocks whose bound beats
   it are split. The result is the best candidate of the whole window, exactly, at a small
   fraction of the cost of scoring them all. Everything is numpy on arrays of candidates x
   points.
2. Gauss-Newton (Levenberg-Marquardt damped) on the bilinearly interpolated likelihood field
   minimises sum (1 - M(T p))² from the correlative pose, reaching a fraction of a cell; a
   refinement that moves more than two cells is refused (it left the basin).
3. What the scan constrains. The Gauss-Newton Hessian (J^T W J of the point-to-line residuals,
   in points' worth of evidence) is the match's information. In a featureless corridor every
   normal points across it, so the information along it is nearly zero: the match says where
   the robot is across the corridor and how it is turned, not how far along it is.
   `weak_directions` finds such directions and `keep_prediction_along` puts the prediction
   (odometry) back along them, so the correlative search's arbitrary pick on a flat ridge never
   moves the robot.
"""
from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from zros.rotations import wrap_angle
from zros.slam.geometry import transform_points
from zros.slam.match_grid import MatchGrid

__all__ = ['SearchWindow', 'MatchResult', 'match_scan', 'correlative_search', 'refine', 'angular_step',
           'weak_directions', 'keep_prediction_along', 'WEAK_INFORMATION', 'CORRIDOR_INFORMATION',
           'ANISOTROPY']

#: Candidates scored in one numpy operation (bounds the candidates x points temporaries).
_CHUNK = 2048
#: [m] point-to-line distance beyond which a pair's weight falls off (Huber).
_HUBER = 0.02
#: A translation direction with less information than this (about this many well-fitting
#: points whose normals point along it) is left to the prediction (module docstring, step 3).
WEAK_INFORMATION = 8.0
#: ... and so is one with less than this, when it also has less than ANISOTROPY times the
#: strongest direction's: a corridor with a door frame or two in range (the bighouse's: 8-20
#: along it, 65-120 across). There the correlative pick lands 3-15 cm off on every scan, mostly
#: backwards, and slid the map 0.5 m in 3 m of corridor. Open ground weak in every direction is
#: not a corridor (turtlebot3_world between the pillars: 10-20 with 35-49 the other way, ratios
#: 0.28-0.55) and its matches stay right: odometry there would carry its heading error along.
#: 20 left the bighouse's room drive 8.6 cm off (its corridor reaches 20.3), 25 3.5 cm.
CORRIDOR_INFORMATION = 25.0
ANISOTROPY = 0.25
_NO_INFORMATION = np.zeros((3, 3))
_NO_INFORMATION.flags.writeable = False


class SearchWindow(NamedTuple):
    """Where to look around the initial pose: +-linear [m] in x and y, +-angular [rad]."""
    linear: float
    angular: float


class MatchResult(NamedTuple):
    """pose: (3,) x, y, yaw; score: mean likelihood 0..1 of the points at `pose`; information:
    (3, 3) the refinement's Hessian at `pose` (x, y, yaw; zeros when it had too few points)."""
    pose: np.ndarray
    score: float
    information: np.ndarray = _NO_INFORMATION


def angular_step(resolution: float, max_range: float) -> float:
    """The rotation [rad] that moves a point `max_range` [m] away by one cell (Olson)."""
    ratio = resolution * resolution / (2.0 * max_range * max_range)
    return math.acos(max(-1.0, 1.0 - ratio))


def match_scan(grid: MatchGrid, points: np.ndarray, initial: np.ndarray, window: SearchWindow, *,
               min_score: float = 0.0) -> MatchResult:
    """Best pose of `points` (N, 2, robot frame) on `grid` within `window` around `initial`
    (a score below `min_score` means no good match was found)."""
    pose, _ = correlative_search(grid, points, initial, window, min_score=min_score)
    return refine(grid, points, pose)


def correlative_search(grid: MatchGrid, points: np.ndarray, initial: np.ndarray, window: SearchWindow, *,
                       min_score: float = 0.0) -> tuple[np.ndarray, float]:
    """The best whole-cell, whole-step pose and its level-0 score (module docstring, step 1).
    Blocks that cannot reach `min_score` are pruned at once; if no pose reaches it, the result
    is the greedy descent's pose, whose score says so."""
    points = np.asarray(points, dtype=np.float64)
    initial = np.asarray(initial, dtype=np.float64)
    res = grid.resolution
    reach = max(float(np.hypot(points[:, 0], points[:, 1]).max()), res)
    step = angular_step(res, reach)
    count = int(math.floor(window.angular / step))
    thetas = initial[2] + step * np.arange(-count, count + 1)
    c, s = np.cos(thetas)[:, None], np.sin(thetas)[:, None]
    world_x = c * points[:, 0] - s * points[:, 1] + initial[0]
    world_y = s * points[:, 0] + c * points[:, 1] + initial[1]
    rows, cols = grid.geometry.world_to_cell(world_x, world_y)                # (A, N)
    radius = int(math.ceil(window.linear / res))
    top = min(len(grid.levels) - 1, max(0, math.ceil(math.log2(2 * radius + 1))))
    starts = np.arange(-radius, radius + 1, 1 << top)
    a, ox, oy = (m.ravel() for m in np.meshgrid(np.arange(len(thetas)), starts, starts, indexing='ij'))

    def score(level: int, a: np.ndarray, ox: np.ndarray, oy: np.ndarray) -> np.ndarray:
        out = np.empty(len(a), dtype=np.float64)
        for i in range(0, len(a), _CHUNK):
            sl = slice(i, i + _CHUNK)
            values = grid.lookup(level, rows[a[sl]] + oy[sl, None], cols[a[sl]] + ox[sl, None])
            out[sl] = values.mean(axis=1)
        return out

    def children(level: int, a: np.ndarray, ox: np.ndarray, oy: np.ndarray) -> tuple[np.ndarray, ...]:
        half = 1 << (level - 1)
        a4 = np.repeat(a, 4)
        ox4 = np.repeat(ox, 4) + np.tile([0, half, 0, half], len(ox))
        oy4 = np.repeat(oy, 4) + np.tile([0, 0, half, half], len(oy))
        keep = (ox4 <= radius) & (oy4 <= radius)
        return a4[keep], ox4[keep], oy4[keep]

    scores = score(top, a, ox, oy)
    # Greedy descent: a real (level-0) score to prune against.
    best_i = int(np.argmax(scores))
    ga, gx, gy = a[best_i:best_i + 1], ox[best_i:best_i + 1], oy[best_i:best_i + 1]
    for level in range(top, 0, -1):
        ga, gx, gy = children(level, ga, gx, gy)
        child_scores = score(level - 1, ga, gx, gy)
        j = int(np.argmax(child_scores))
        ga, gx, gy, best_score = ga[j:j + 1], gx[j:j + 1], gy[j:j + 1], float(child_scores[j])
    if top == 0:
        best_score = float(scores[best_i])
    best = (int(ga[0]), int(gx[0]), int(gy[0]))
    # Branch and bound, level by level: only blocks that could beat the best so far.
    bound = max(best_score, min_score)
    keep = scores > bound
    a, ox, oy = a[keep], ox[keep], oy[keep]
    for level in range(top, 0, -1):
        if len(a) == 0:
            break
        a, ox, oy = children(level, a, ox, oy)
        scores = score(level - 1, a, ox, oy)
        keep = scores > bound
        a, ox, oy, scores = a[keep], ox[keep], oy[keep], scores[keep]
    if len(a):
        j = int(np.argmax(scores))
        best, best_score = (int(a[j]), int(ox[j]), int(oy[j])), float(scores[j])
    pose = np.array([initial[0] + best[1] * res, initial[1] + best[2] * res, wrap_angle(thetas[best[0]])])
    return pose, best_score


def refine(grid: MatchGrid, points: np.ndarray, pose: np.ndarray, *, iterations: int = 10,
           max_distance: float = 0.1) -> MatchResult:
    """Gauss-Newton on point-to-line distances (module docstring, step 2)."""
    points = np.asarray(points, dtype=np.float64)
    start = np.asarray(pose, dtype=np.float64)
    tree, centroid, normal, linear = grid.surfaces()
    current = start.copy()
    information = np.zeros((3, 3))
    for _ in range(iterations):
        world = transform_points(current, points)
        distance, index = tree.query(world, distance_upper_bound=max_distance)
        valid = np.isfinite(distance)
        if valid.sum() < 3:
            break
        w, idx, src = world[valid], index[valid], points[valid]
        n = normal[idx]
        residual = np.einsum('ij,ij->i', w - centroid[idx], n)
        c, s = math.cos(current[2]), math.sin(current[2])
        dwx = -s * src[:, 0] - c * src[:, 1]
        dwy = c * src[:, 0] - s * src[:, 1]
        jacobian = np.column_stack([n[:, 0], n[:, 1], n[:, 0] * dwx + n[:, 1] * dwy])
        weight = linear[idx] / np.maximum(1.0, np.abs(residual) / _HUBER)        # Huber, line-likeness
        hessian = (jacobian * weight[:, None]).T @ jacobian
        information = hessian
        if np.linalg.cond(hessian) > 1e9:
            break
        delta = -np.linalg.solve(hessian, (jacobian * weight[:, None]).T @ residual)
        current = current + delta
        current[2] = wrap_angle(current[2])
        if abs(delta[0]) + abs(delta[1]) < 1e-5 and abs(delta[2]) < 1e-5:
            break
    if math.hypot(current[0] - start[0], current[1] - start[1]) > 2.0 * grid.resolution:
        current = start
    value, _ = grid.interpolate(transform_points(current, points))
    return MatchResult(current, float(value.mean()), information)


def weak_directions(information: np.ndarray, *, threshold: float = WEAK_INFORMATION,
                    corridor: float = CORRIDOR_INFORMATION, anisotropy: float = ANISOTROPY) -> np.ndarray:
    """(K, 2) unit vectors (map frame) of the translation directions the match does not
    constrain: eigenvectors of the information's x-y block (the yaw marginalised out, via the
    Schur complement) with eigenvalue below `threshold`, or below `corridor` and `anisotropy`
    times the largest eigenvalue. K is 0, 1 (a corridor) or 2 (nothing to match)."""
    info = np.asarray(information, dtype=np.float64)
    xy = info[:2, :2]
    if info[2, 2] > 1e-9:
        xy = xy - np.outer(info[:2, 2], info[2, :2]) / info[2, 2]
    values, vectors = np.linalg.eigh((xy + xy.T) / 2.0)
    weak = (values < threshold) | ((values < corridor) & (values < anisotropy * values.max()))
    return vectors[:, weak].T


def keep_prediction_along(matched: np.ndarray, predicted: np.ndarray, directions: np.ndarray) -> np.ndarray:
    """`matched` (x, y, yaw) with its translation along each of `directions` (K, 2, unit,
    orthogonal) put back to `predicted`'s: the match corrects only what the scan constrains."""
    pose = np.array(matched, dtype=np.float64)
    offset = pose[:2] - np.asarray(predicted, dtype=np.float64)[:2]
    for direction in np.asarray(directions, dtype=np.float64).reshape(-1, 2):
        pose[:2] -= direction * float(offset @ direction)
    return pose
