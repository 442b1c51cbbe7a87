"""zros.slam.loop_check: a loop closure that would move the graph is taken only on a near-perfect
fit, and a closure pulls only along the directions its scan pins down."""
from __future__ import annotations

import numpy as np

from zros.slam.geometry import relative
from zros.slam.loop_check import closure_information, is_ambiguous
from zros.slam.match_grid import MatchGrid
from zros.slam.matcher import SearchWindow, match_scan, refine

FLOOR = np.diag([0.01 ** -2, 0.01 ** -2, 0.005 ** -2])      # Slam's loop_sigma_xy, loop_sigma_yaw


def _corridor_with_posts() -> np.ndarray:
    """A 2 m wide corridor with a few 0.3 m posts on its walls: most of a scan is two parallel
    walls, which fit anywhere along it; the posts say where (the bighouse corridor, in small)."""
    t = np.arange(-6.0, 6.0, 0.02)
    walls = [np.column_stack([t, np.full_like(t, 1.0)]), np.column_stack([t, np.full_like(t, -1.0)])]
    stub = np.arange(0.0, 0.3, 0.02)
    for x, side in ((-2.9, 1), (-1.3, -1), (-0.6, 1), (0.5, 1), (1.2, -1), (2.7, 1)):
        walls.append(np.column_stack([np.full_like(stub, x), side * (1.0 - stub)]))
    return np.vstack(walls)


def test_a_match_that_moves_the_keyframe_needs_a_near_perfect_fit():
    reference = _corridor_with_posts()
    grid = MatchGrid(reference, 0.025, sigma=0.05)
    truth = np.array([0.1, 0.05, 0.0])
    points = relative(truth, np.column_stack([reference, np.zeros(len(reference))]))[:, :2]
    points = points[np.hypot(points[:, 0], points[:, 1]) < 3.5]           # what the LDS-01 reaches
    right = refine(grid, points, truth)
    look_alike = refine(grid, points, truth + np.array([0.3, 0.0, 0.0]))   # the walls fit, the posts do not
    assert right.score > 0.95 > look_alike.score > 0.85                  # a fair score: not a loop's
    # The graph had the keyframe right, the search landed 0.3 m along: rejected.
    assert is_ambiguous(look_alike.score, 0.3, min_response=0.95, tolerance=0.05)
    # The graph had drifted 0.15 m, the match puts it back at the truth: a loop.
    found = match_scan(grid, points, truth + np.array([0.15, 0.0, 0.0]), SearchWindow(0.5, 0.3))
    assert np.hypot(*(found.pose[:2] - truth[:2])) < 0.01
    assert not is_ambiguous(found.score, 0.15, min_response=0.95, tolerance=0.05)
    # A fair match that hardly moves the keyframe only confirms the graph: kept.
    assert not is_ambiguous(0.7, 0.02, min_response=0.95, tolerance=0.05)


def test_closure_information_is_the_floor_where_the_scan_is_rich_and_weak_where_it_is_not():
    rich = np.diag([1e6, 1e6, 1e7])
    assert np.allclose(closure_information(rich, FLOOR, 0.05), FLOOR, rtol=1e-2)
    corridor = np.diag([2.0, 150.0, 400.0])           # little along x: a corridor's walls
    info = closure_information(corridor, FLOOR, 0.05)
    sigma = np.sqrt(np.diag(np.linalg.inv(info)))
    assert sigma[0] > 0.03                             # along the corridor: centimetres, not the floor's 1
    assert 0.01 < sigma[1] < 0.0115                    # across it: about the floor
    assert np.allclose(info, info.T)
    nothing = closure_information(np.zeros((3, 3)), FLOOR, 0.05)
    assert np.all(np.linalg.eigvalsh(nothing) > 0) and np.sqrt(np.linalg.inv(nothing)[0, 0]) > 1.0
