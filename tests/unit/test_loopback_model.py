"""The loopback simulator's model: a lidar that sees a map's cells, and motion with no dynamics."""
from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from zros.grid_geometry import GridGeometry
from zros.sim.grid_lidar import GridLidar, occupied_outline
from zros.sim.robot import integrate_twist


def _room(size: int = 40, resolution: float = 0.1) -> tuple[np.ndarray, GridGeometry]:
    """A size x size grid at the origin: a one-cell wall round its rim, one 2 x 2 cell block."""
    grid = np.zeros((size, size), dtype=np.int8)
    grid[0, :] = grid[-1, :] = grid[:, 0] = grid[:, -1] = 100
    grid[30:32, 10:12] = 100
    return grid, GridGeometry(resolution, (0.0, 0.0), (size, size))


def test_the_outline_of_one_cell_is_its_four_sides() -> None:
    edges = occupied_outline(np.array([[False, False], [False, True]]), GridGeometry(0.5, (1.0, 2.0), (2, 2)))
    assert sorted(map(tuple, edges.tolist())) == sorted([
        (1.5, 2.5, 2.0, 2.5), (1.5, 3.0, 2.0, 3.0), (1.5, 2.5, 1.5, 3.0), (2.0, 2.5, 2.0, 3.0)])


def test_collinear_borders_merge_into_one_segment() -> None:
    """A 1 x 5 bar is 4 segments, not 12: the scan costs per wall, not per cell."""
    occupied = np.zeros((3, 7), dtype=bool)
    occupied[1, 1:6] = True
    edges = occupied_outline(occupied, GridGeometry(1.0, (0.0, 0.0), (3, 7)))
    assert len(edges) == 4
    lengths = np.hypot(edges[:, 2] - edges[:, 0], edges[:, 3] - edges[:, 1])
    assert sorted(lengths.tolist()) == [1.0, 1.0, 5.0, 5.0]


def test_a_shape_mismatch_is_one_error_line() -> None:
    with pytest.raises(ValueError, match='does not match'):
        occupied_outline(np.zeros((3, 4), dtype=bool), GridGeometry(1.0, (0.0, 0.0), (4, 3)))


def test_beams_end_on_the_cell_borders_of_the_map() -> None:
    grid, geometry = _room()
    lidar = GridLidar(grid, geometry)
    # From (2.0, 2.0): the inner face of the east rim is x = 3.9, of the north rim y = 3.9; the block
    # covers x 1.0..1.2, y 3.0..3.2, so straight up from (1.1, 2.0) it is 1.0 m away.
    east, north, west = lidar.scan((2.0, 2.0, 0.0), 0.0, math.pi / 2, 3, 30.0)
    assert east == pytest.approx(1.9) and north == pytest.approx(1.9) and west == pytest.approx(1.9)
    assert lidar.scan((1.1, 2.0, math.pi / 2), 0.0, 0.1, 1, 30.0)[0] == pytest.approx(1.0)


def test_unknown_cells_and_the_space_off_the_map_reflect_nothing() -> None:
    grid = np.full((20, 20), -1, dtype=np.int8)
    grid[5:15, 5:15] = 0
    grid[10, 18] = 59                                    # below Nav2's 60: free
    lidar = GridLidar(grid, GridGeometry(0.1, (0.0, 0.0), (20, 20)))
    assert np.isinf(lidar.scan((1.0, 1.0, 0.0), -math.pi, 0.1, 60, 30.0)).all()
    grid[10, 18] = 60
    lidar = GridLidar(grid, GridGeometry(0.1, (0.0, 0.0), (20, 20)))
    assert lidar.scan((1.0, 1.05, 0.0), 0.0, 0.1, 1, 30.0)[0] == pytest.approx(0.8)
    assert lidar.scan((1.0, 1.05, 0.0), 0.0, 0.1, 1, 0.5)[0] == math.inf      # beyond range_max
    assert np.isinf(lidar.scan((-1.0, 1.05, 0.0), 0.0, 0.1, 5, 30.0)).all()   # sensor off the map


def test_the_map_origin_and_its_yaw_place_the_walls() -> None:
    grid, _ = _room()
    turned = GridLidar(grid, GridGeometry(0.1, (10.0, -5.0, math.pi / 2), (40, 40)))
    # The grid's +x now points along the world's +y: from the grid's (2, 2) the rim is 1.9 m away.
    x, y = 10.0 - 2.0, -5.0 + 2.0
    assert turned.scan((x, y, math.pi / 2), 0.0, math.pi / 2, 4, 30.0) == pytest.approx([1.9] * 4)


def test_a_scan_agrees_with_a_fine_ray_march() -> None:
    """Cross-check against the obvious method (step along each beam, stop in the first occupied
    cell), which is at most one step short."""
    grid, geometry = _room()
    lidar = GridLidar(grid, geometry)
    angles = np.linspace(-math.pi, math.pi, 240, endpoint=False)
    exact = lidar.scan((1.73, 2.41, 0.3), -math.pi, 2 * math.pi / 240, 240, 30.0)
    steps = np.arange(0.0, 6.0, 0.001)
    xs = 1.73 + np.cos(angles + 0.3)[:, None] * steps
    ys = 2.41 + np.sin(angles + 0.3)[:, None] * steps
    rows, cols = geometry.world_to_cell(xs, ys)
    hit = grid[np.clip(rows, 0, 39), np.clip(cols, 0, 39)] >= 60
    marched = steps[np.argmax(hit, axis=1)]
    assert np.abs(exact - marched).max() <= 0.0011


def test_twist_integration_is_in_the_body_frame() -> None:
    assert integrate_twist((1.0, 2.0, math.pi / 2), (0.5, 0.0, 0.0), 2.0) == pytest.approx((1.0, 3.0, math.pi / 2))
    assert integrate_twist((0.0, 0.0, 0.0), (0.0, 0.2, 0.0), 1.0) == pytest.approx((0.0, 0.2, 0.0))
    x, y, yaw = integrate_twist((0.0, 0.0, 3.0), (0.0, 0.0, 1.0), 0.5)
    assert yaw == pytest.approx(3.5 - 2 * math.pi)                             # wrapped


@settings(max_examples=50, deadline=None)
@given(st.floats(0.05, 0.5), st.floats(-1.0, 1.0).filter(lambda w: abs(w) > 0.1))
def test_steps_along_an_arc_stay_on_the_circle(v: float, w: float) -> None:
    """100 Hz steps of a constant (v, w) stay on the circle of radius v / w round its centre
    (first-order steps drift outwards by about v * dt / 2 per turn, well under a millimetre)."""
    pose = (0.0, 0.0, 0.0)
    for _ in range(int(2.0 / 0.01)):
        pose = integrate_twist(pose, (v, 0.0, w), 0.01)
    radius = v / w
    assert math.hypot(pose[0], pose[1] - radius) == pytest.approx(abs(radius), abs=1e-3 + v * 0.01)
