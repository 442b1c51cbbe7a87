"""Path smoothing: nav2_smoother's SimpleSmoother, as plain numpy.

Each iteration moves every inner point towards its original position (weight `w_data`) and
towards the middle of its neighbours (weight `w_smooth`), until the points move less than
`tolerance` [m] in total in one iteration. The ends stay. Nav2 updates the points one after the
other (Gauss-Seidel); here all at once per iteration (Jacobi), which converges to the same path.
An iteration that would put a point in a lethal or inscribed cell is undone and smoothing stops
there, as does running out of `max_its` or time: the result is then the last admissible path and
"not completed". With `do_refinement` the smoothed path is smoothed again `refinement_num` times
(anchored to itself), which straightens it further.

A path that reverses (a cusp: consecutive steps pointing more than 90° apart) is smoothed one
directional segment at a time, segments of 10 points or fewer are left alone, and the headings
are then recomputed from the points (flipped on segments driven backwards).

Reference: navigation2 nav2_smoother (simple_smoother.cpp, smoother_utils.hpp) and its
configuration guide.
"""
from __future__ import annotations

import time
from dataclasses import dataclass, fields
from typing import Callable, NamedTuple

import numpy as np

from zros.navigation.costmap import MAX_NON_OBSTACLE, NO_INFORMATION
from zros.rotations import wrap_angle

__all__ = ['SimpleSmootherParams', 'Smoothed', 'smooth_path', 'taut_step', 'directional_segments', 'approximate_yaws']

_MIN_SEGMENT_STEPS = 9   # Nav2 smooths a segment only if end - start > 9


@dataclass
class SimpleSmootherParams:
    """nav2_smoother::SimpleSmoother's parameters (names and defaults as Nav2's)."""

    tolerance: float = 1e-10    # [m] total movement of an iteration below which it has converged
    max_its: int = 1000
    w_data: float = 0.2         # pull towards the original points
    w_smooth: float = 0.3       # pull towards the neighbours' middle
    do_refinement: bool = True
    refinement_num: int = 2     # Jazzy's parameter; Humble refines up to 4 times

    @classmethod
    def names(cls) -> list[str]:
        return [f.name for f in fields(cls)]


class Smoothed(NamedTuple):
    """A smoothing's outcome: (N, 2) points [m], (N,) headings [rad], and whether it converged
    within `max_its` and the time allowed without meeting an obstacle."""

    points: np.ndarray
    yaws: np.ndarray
    completed: bool


CostAt = Callable[[np.ndarray], np.ndarray]


def taut_step(path: np.ndarray, original: np.ndarray, w_data: float, w_smooth: float) -> np.ndarray:
    """The inner points after one smoothing update, (N-2, 2): the data term pulls each towards
    `original`, the smoothing term towards the mean of its neighbours in `path`."""
    inner = path[1:-1]
    return inner + w_data * (original[1:-1] - inner) + w_smooth * (path[:-2] + path[2:] - 2.0 * inner)


def directional_segments(points: np.ndarray) -> list[tuple[int, int]]:
    """(start, end) index pairs, ends inclusive, of the parts of a path between cusps (where
    the direction of travel turns by more than 90°); neighbouring segments share the cusp."""
    steps = np.diff(points, axis=0)
    cusps = np.flatnonzero(np.einsum('ij,ij->i', steps[:-1], steps[1:]) < 0.0) + 1
    bounds = [0, *cusps.tolist(), len(points) - 1]
    return list(zip(bounds[:-1], bounds[1:]))


def approximate_yaws(points: np.ndarray, yaws: np.ndarray) -> np.ndarray:
    """Headings [rad] pointing each pose at the next (flipped by π if the segment is driven
    backwards, judged by the second pose's given heading); the last pose and poses on top of
    their successor keep theirs."""
    out = np.array(yaws, np.float64)
    if len(points) < 3:
        return out
    steps = np.diff(points, axis=0)
    travel = np.arctan2(steps[:, 1], steps[:, 0])
    reversing = abs(wrap_angle(yaws[1] - travel[1])) > np.pi / 2
    moving = (np.abs(steps) >= 1e-4).any(axis=1)
    out[:-1][moving] = wrap_angle(travel[moving] + (np.pi if reversing else 0.0))
    return out


def smooth_path(points: np.ndarray, yaws: np.ndarray, params: SimpleSmootherParams, *,
                cost_at: CostAt | None = None, max_time: float = np.inf) -> Smoothed:
    """Smooth a path as SimpleSmoother does.

    Parameters
    ----------
    points : (N, 2) ndarray
        The path [m].
    yaws : (N,) ndarray
        Its headings [rad]; used to tell reversing segments, and kept where no new one is found.
    params : SimpleSmootherParams
    cost_at : callable, optional
        (M, 2) points -> (M,) costs (nav2_costmap_2d values); without it nothing is in collision.
    max_time : float
        Seconds allowed (wall clock) before smoothing stops with the last path, not completed.

    Returns
    -------
    Smoothed
        ``Smoothed(points, yaws, completed)``; the input arrays are not modified.
    """
    deadline = time.monotonic() + max_time
    path = np.array(points, np.float64).reshape(-1, 2)
    new_yaws = np.array(yaws, np.float64)
    completed = True
    for start, end in directional_segments(path) if len(path) > 2 else []:
        if end - start <= _MIN_SEGMENT_STEPS:
            continue
        segment, ok = _smooth_segment(path[start:end + 1], params, cost_at, deadline)
        refinements = params.refinement_num if params.do_refinement and ok else 0
        for _ in range(refinements):
            segment, _refined = _smooth_segment(segment, params, cost_at, deadline)
        path[start:end + 1] = segment
        new_yaws[start:end + 1] = approximate_yaws(segment, new_yaws[start:end + 1])
        completed = completed and ok
    return Smoothed(path, new_yaws, completed)


def _smooth_segment(original: np.ndarray, params: SimpleSmootherParams, cost_at: CostAt | None,
                    deadline: float) -> tuple[np.ndarray, bool]:
    """One SimpleSmoother run on a directional segment: (points, converged)."""
    path = original.copy()
    for _ in range(max(params.max_its - 1, 0)):
        if time.monotonic() > deadline:
            return path, False
        update = taut_step(path, original, params.w_data, params.w_smooth)
        if cost_at is not None:
            costs = cost_at(update)
            if ((costs > MAX_NON_OBSTACLE) & (costs != NO_INFORMATION)).any():
                return path, False
        change = float(np.abs(update - path[1:-1]).sum())
        path[1:-1] = update
        if change < params.tolerance:
            return path, True
    return path, False
