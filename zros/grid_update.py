"""Incremental occupancy grids: the rectangle that changed, as map_msgs/OccupancyGridUpdate carries it.

Nav2's costmaps publish the whole grid on `<costmap>/costmap` only when they must (the first
time, when the size, resolution or origin changes, or always with `always_send_full_costmap`),
and otherwise only the rectangle of cells that changed on `<costmap>/costmap_updates`; RViz's
Map display pastes each such patch into the last full grid. On a slow link that is the
difference between a few hundred bytes and the whole grid a second. The publisher side
(`changed_bounds`, `patch`) and the subscriber side (`apply_update`) live here together, so that
what one cuts out the other puts back in the same place.

Conventions are nav_msgs/OccupancyGrid's (zros.grid_geometry): a grid is a (height, width)
array, row 0 the lowest y; an update's `x`, `y` are the column and row of its first cell, and
its data is `height` rows of `width` cells, row-major.
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np

__all__ = ['Bounds', 'apply_update', 'changed_bounds', 'patch']


class Bounds(NamedTuple):
    """A rectangle of cells: columns x0 <= x < xn, rows y0 <= y < yn (Nav2's order of names)."""

    x0: int
    xn: int
    y0: int
    yn: int

    @property
    def width(self) -> int:
        return self.xn - self.x0

    @property
    def height(self) -> int:
        return self.yn - self.y0


def changed_bounds(previous: np.ndarray, current: np.ndarray) -> Bounds | None:
    """The smallest rectangle holding every cell where `current` differs from `previous`, or
    None when none does.

    Raises:
        ValueError: the grids differ in shape (a change of size is sent whole, never as a patch).
    """
    if previous.shape != current.shape:
        raise ValueError(f'grids of different shapes {previous.shape} and {current.shape} have no patch')
    changed = previous != current
    rows = np.flatnonzero(changed.any(axis=1))
    if rows.size == 0:
        return None
    cols = np.flatnonzero(changed.any(axis=0))
    return Bounds(int(cols[0]), int(cols[-1]) + 1, int(rows[0]), int(rows[-1]) + 1)


def patch(grid: np.ndarray, bounds: Bounds) -> np.ndarray:
    """The cells of `grid` inside `bounds`, flat and row-major (an update's `data`)."""
    return np.ascontiguousarray(grid[bounds.y0:bounds.yn, bounds.x0:bounds.xn]).ravel()


def apply_update(grid: np.ndarray, x: int, y: int, width: int, height: int, data: np.ndarray) -> None:
    """Paste an update's `data` (`height` x `width` cells whose first is column `x`, row `y`)
    into `grid`, in place.

    Raises:
        ValueError: the update does not fit the grid, or its data is not width x height cells
            (RViz refuses such an update too: it was cut from a grid of another size).
    """
    rows, cols = grid.shape
    if x < 0 or y < 0 or x + width > cols or y + height > rows:
        raise ValueError(f'update of {width} x {height} cells at ({x}, {y}) is outside the {cols} x {rows} grid')
    cells = np.asarray(data)
    if cells.size != width * height:
        raise ValueError(f'update of {width} x {height} cells carries {cells.size} values')
    grid[y:y + height, x:x + width] = cells.reshape(height, width)
