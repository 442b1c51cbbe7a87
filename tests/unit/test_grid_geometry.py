"""zros.grid_geometry: the one placement of cells shared by every occupancy grid (pure, no processes).

Property-based (hypothesis) for the round trips and the half-cell convention, plus checks that
the grid classes hand out the same geometry for the same map.
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from zros.amcl.map_grid import MapGrid
from zros.grid_geometry import GridGeometry
from zros.map_io import OccupancyMap
from zros.navigation.costmap import CostmapParams, LayeredCostmap
from zros.sim import load_world, rasterize
from zros.slam.grid import LogOddsGrid
from zros.slam.match_grid import MatchGrid

finite = st.floats(min_value=-1e3, max_value=1e3, allow_nan=False)
geometries = st.builds(
    GridGeometry,
    resolution=st.floats(min_value=0.01, max_value=2.0),
    origin=st.tuples(finite, finite, st.floats(min_value=-math.pi, max_value=math.pi)),
    shape=st.tuples(st.integers(1, 500), st.integers(1, 500)),
)
# Exact binary fractions, so that a point on a cell border is exactly on it.
dyadic_geometries = st.builds(
    GridGeometry,
    resolution=st.sampled_from([0.03125, 0.0625, 0.25, 0.5, 1.0, 2.0]),
    origin=st.tuples(st.integers(-64, 64).map(float), st.integers(-64, 64).map(float)),
    shape=st.tuples(st.integers(1, 200), st.integers(1, 200)),
)


def cells_of(geometry: GridGeometry) -> st.SearchStrategy[tuple[int, int]]:
    return st.tuples(st.integers(0, geometry.height - 1), st.integers(0, geometry.width - 1))


@given(data=st.data(), geometry=geometries)
def test_a_cells_centre_lies_in_that_cell(data: st.DataObject, geometry: GridGeometry) -> None:
    row, col = data.draw(cells_of(geometry))
    x, y = geometry.cell_centre(row, col)
    assert geometry.world_to_cell(x, y) == (row, col)


@given(geometry=geometries, x=finite, y=finite)
def test_continuous_cells_and_corners_are_inverses(geometry: GridGeometry, x: float, y: float) -> None:
    back = geometry.cell_corner(*geometry.world_to_cell_continuous(x, y))
    assert np.allclose(back, (x, y), rtol=0.0, atol=1e-9)


@given(data=st.data(), geometry=dyadic_geometries)
def test_a_cell_holds_its_lower_left_corner_and_not_its_upper_right_one(data: st.DataObject,
                                                                      geometry: GridGeometry) -> None:
    """[col, col + 1) x [row, row + 1): the corner belongs to the cell, the far edges to the next."""
    row, col = data.draw(cells_of(geometry))
    x, y = geometry.cell_corner(row, col)
    assert geometry.world_to_cell(x, y) == (row, col)
    step = geometry.resolution
    assert geometry.world_to_cell(x + step, y + step) == (row + 1, col + 1)
    fx, fy = (data.draw(st.integers(0, 1023)) / 1024 for _ in range(2))      # exact fractions < 1
    assert geometry.world_to_cell(x + fx * step, y + fy * step) == (row, col)


def test_index_order_is_row_then_col_and_the_centre_is_half_a_cell_in() -> None:
    geometry = GridGeometry(0.5, (-1.0, 2.0), (3, 4))
    assert geometry.cell_centre(0, 0) == (-0.75, 2.25)
    assert geometry.cell_centre(2, 1) == (-0.25, 3.25)                 # row is y, col is x
    assert geometry.world_to_cell(0.9, 2.1) == (0, 3)
    assert (geometry.height, geometry.width) == (3, 4)


def test_a_rotated_origin_turns_the_rows() -> None:
    geometry = GridGeometry(1.0, (0.0, 0.0, math.pi / 2), (2, 2))
    x, y = geometry.cell_centre(0, 0)
    assert math.isclose(x, -0.5) and math.isclose(y, 0.5)             # columns run along +y
    assert geometry.world_to_cell(-1.5, 0.5) == (1, 0)                 # rows run along -x


@given(data=st.data(), geometry=geometries)
def test_flat_indices_are_row_major(data: st.DataObject, geometry: GridGeometry) -> None:
    row, col = data.draw(cells_of(geometry))
    flat = geometry.index(row, col)
    assert flat == np.ravel_multi_index((row, col), geometry.shape)
    assert geometry.cell_of_index(flat) == (row, col)


@given(geometry=dyadic_geometries, rows=st.lists(st.integers(-300, 300), min_size=1, max_size=20),
       cols=st.lists(st.integers(-300, 300), min_size=1, max_size=20))
def test_contains_and_clipping_agree(geometry: GridGeometry, rows: list[int], cols: list[int]) -> None:
    n = min(len(rows), len(cols))
    rows_a, cols_a = np.array(rows[:n]), np.array(cols[:n])
    x, y = geometry.cell_centre(rows_a, cols_a)
    clipped_rows, clipped_cols, inside = geometry.world_to_cell_clipped(x, y)
    expected = (rows_a >= 0) & (rows_a < geometry.height) & (cols_a >= 0) & (cols_a < geometry.width)
    assert np.array_equal(inside, expected) and np.array_equal(geometry.contains(rows_a, cols_a), expected)
    assert np.array_equal(clipped_rows[inside], rows_a[inside]) and np.array_equal(clipped_cols[inside], cols_a[inside])
    assert ((0 <= clipped_rows) & (clipped_rows < geometry.height)).all()
    assert ((0 <= clipped_cols) & (clipped_cols < geometry.width)).all()


@settings(max_examples=20)
@given(geometry=geometries)
def test_centres_cover_the_grid_in_index_order(geometry: GridGeometry) -> None:
    small = GridGeometry(geometry.resolution, geometry.origin, (min(geometry.height, 7), min(geometry.width, 5)))
    x, y = small.centres()
    assert x.shape == small.shape
    rows, cols = small.world_to_cell(x, y)
    assert np.array_equal(rows, np.arange(small.height)[:, None].repeat(small.width, axis=1))
    assert np.array_equal(cols, np.arange(small.width)[None, :].repeat(small.height, axis=0))


@pytest.mark.parametrize('kwargs, message', [
    ({'resolution': 0.0}, 'resolution'),
    ({'resolution': float('nan')}, 'resolution'),
    ({'resolution': 0.1, 'origin': (0.0, float('inf'))}, 'origin'),
    ({'resolution': 0.1, 'origin': (1.0,)}, 'origin'),
    ({'resolution': 0.1, 'shape': (-1, 3)}, 'shape'),
])
def test_bad_geometry_is_one_clear_error(kwargs: dict, message: str) -> None:
    with pytest.raises(ValueError, match=message):
        GridGeometry(**kwargs)


def test_an_xy_origin_means_yaw_zero_and_values_are_normalised() -> None:
    geometry = GridGeometry(np.float32(0.5), np.array([1, 2]), (np.int64(3), 4))
    assert geometry == GridGeometry(0.5, (1.0, 2.0, 0.0), (3, 4))
    assert type(geometry.resolution) is float and type(geometry.shape[0]) is int


def test_the_grids_of_one_map_share_one_geometry() -> None:
    raster = rasterize(load_world('turtlebot3_world'), 0.05)
    expected = GridGeometry(0.05, raster.origin, raster.cells.shape)
    assert raster.geometry == expected
    amcl = MapGrid(raster.occupancy_data(), resolution=0.05, origin=raster.origin, width=raster.width)
    assert amcl.geometry == expected
    occupancy = OccupancyMap(raster.occupancy_data().reshape(raster.cells.shape), 0.05, (*raster.origin, 0.0))
    assert occupancy.geometry == expected
    costmap = LayeredCostmap(CostmapParams(resolution=0.05))
    costmap.set_static_map(occupancy.data, 0.05, raster.origin)
    assert costmap.geometry == expected
    # Every grid finds the centre of an occupied cell in that cell.
    cell = tuple(int(i) for i in np.argwhere(raster.cells)[len(np.argwhere(raster.cells)) // 2])
    x, y = expected.cell_centre(*cell)
    assert raster.cell_of(x, y) == cell
    rows, cols, inside = amcl.cells(np.array([x]), np.array([y]))
    assert inside[0] and (rows[0], cols[0]) == cell
    assert costmap.cost_at(np.array([[x, y]]))[0] == 254


def test_the_slam_grids_place_cells_on_the_same_lattice() -> None:
    points = np.array([[0.26, 0.51], [1.0, -0.3]])
    match = MatchGrid(points, 0.05, levels=1)
    rows, cols = match.geometry.world_to_cell(points[:, 0], points[:, 1])
    assert (match.levels[0][rows, cols] > 0.5).all()                   # the field peaks at its points
    grid = LogOddsGrid(0.05)
    assert grid.geometry.shape == (0, 0)
    assert grid.lattice.world_to_cell(0.26, 0.51) == (10, 5)
