"""zros.grid_update: the changed rectangle of a grid, cut out by the costmap and pasted back by a
subscriber (map_msgs/OccupancyGridUpdate), pure numpy, no processes."""
from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from zros.grid_update import Bounds, apply_update, changed_bounds, patch


def test_no_change_has_no_bounds():
    grid = np.zeros((4, 6), np.int8)
    assert changed_bounds(grid, grid.copy()) is None


def test_bounds_hold_every_changed_cell_and_nothing_more():
    before = np.zeros((5, 8), np.int8)
    after = before.copy()
    after[1, 2] = 100          # row 1, column 2
    after[3, 6] = -1           # row 3, column 6
    bounds = changed_bounds(before, after)
    assert bounds == Bounds(x0=2, xn=7, y0=1, yn=4)
    assert (bounds.width, bounds.height) == (5, 3)


def test_patch_is_row_major_from_the_first_cell():
    grid = np.arange(20, dtype=np.int8).reshape(4, 5)
    assert patch(grid, Bounds(1, 3, 2, 4)).tolist() == [11, 12, 16, 17]


def test_a_change_of_shape_is_never_a_patch():
    with pytest.raises(ValueError, match='different shapes'):
        changed_bounds(np.zeros((3, 3), np.int8), np.zeros((3, 4), np.int8))


@pytest.mark.parametrize('x, y, width, height, cells', [
    (3, 0, 2, 1, 2),           # past the right edge
    (0, 3, 1, 2, 2),           # past the top
    (-1, 0, 1, 1, 1),
    (0, 0, 2, 2, 3),           # data not width x height
])
def test_an_update_that_does_not_fit_is_refused(x, y, width, height, cells):
    grid = np.zeros((4, 4), np.int8)
    with pytest.raises(ValueError):
        apply_update(grid, x, y, width, height, np.ones(cells, np.int8))
    assert not grid.any()      # and the grid is left as it was


grids = st.integers(1, 12).flatmap(lambda h: st.integers(1, 12).flatmap(lambda w: st.tuples(
    st.lists(st.integers(-1, 100), min_size=h * w, max_size=h * w),
    st.lists(st.integers(-1, 100), min_size=h * w, max_size=h * w),
    st.just((h, w)))))


@settings(max_examples=200, deadline=None)
@given(grids)
def test_pasting_the_patch_into_the_old_grid_gives_the_new_one(case):
    old, new, shape = case
    before = np.array(old, np.int8).reshape(shape)
    after = np.array(new, np.int8).reshape(shape)
    received = before.copy()   # what a subscriber holds from the last full grid
    bounds = changed_bounds(before, after)
    if bounds is not None:
        apply_update(received, bounds.x0, bounds.y0, bounds.width, bounds.height, patch(after, bounds))
    assert np.array_equal(received, after)
