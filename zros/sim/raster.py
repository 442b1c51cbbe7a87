"""The ground-truth occupancy grid of a world, exact at any resolution.

What "occupied" means here: a cell is occupied when its interior overlaps an obstacle, however
little. That is what a perfect mapper marks (a lidar beam that ends on a 1 cm shelf board marks
the cell the board is in), so a SLAM map is compared against the cells it could know about. A
zero-thickness segment marks every cell whose interior it passes through (both neighbours when
it lies exactly on a cell border).

How, exactly and without a loop per cell:
- polygons: a cell overlaps a polygon iff its centre is inside (even-odd, one crossing count
  per row, accumulated with a cumulative sum) or the polygon's boundary passes through the
  cell's interior. The boundary's cells come from cutting every side at the grid lines it
  crosses: the midpoint of each piece lies inside exactly the cell that piece passes through.
- circles: a cell overlaps a disc iff the cell's nearest point to the centre is inside the disc.

Layout follows nav_msgs/OccupancyGrid: `cells[row, col]` covers
x in [ox + col * res, ox + (col + 1) * res), y in [oy + row * res, ...): row 0 is the lowest y.
"""
from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from zros.grid_geometry import GridGeometry
from zros.sim.world import World, loop_edges

__all__ = ['OccupancyRaster', 'rasterize']

# Grid coordinates within this fraction of a cell of a grid line count as on it.
_ON_LINE = 1e-9


class OccupancyRaster(NamedTuple):
    """A world's occupancy at one resolution.

    cells: (height, width) bool, True where the cell overlaps an obstacle; row 0 is the lowest y.
    origin: (x, y) [m] of the lower-left corner of cell (0, 0).
    resolution: cell size [m].
    """
    cells: np.ndarray
    origin: tuple[float, float]
    resolution: float

    @property
    def geometry(self) -> GridGeometry:
        """Where the cells lie (yaw 0: the raster is aligned with the world's axes)."""
        return GridGeometry(self.resolution, self.origin, self.cells.shape)

    @property
    def width(self) -> int:
        return int(self.cells.shape[1])

    @property
    def height(self) -> int:
        return int(self.cells.shape[0])

    def occupancy_data(self) -> np.ndarray:
        """The cells as nav_msgs/OccupancyGrid `data` (int8, 100 occupied / 0 free, row-major)."""
        return np.where(self.cells, 100, 0).astype(np.int8).ravel()

    def cell_of(self, x: float, y: float) -> tuple[int, int]:
        """(row, col) of the cell containing the point (x, y) [m] (may be outside the grid)."""
        row, col = self.geometry.world_to_cell(x, y)
        return int(row), int(col)


def rasterize(world: World, resolution: float, *, origin: tuple[float, float] | None = None,
              size: tuple[int, int] | None = None, margin: float = 0.5) -> OccupancyRaster:
    """The occupancy of `world` on a grid of `resolution` [m] cells.

    Args:
        world: the world.
        resolution: cell size [m], > 0.
        origin: lower-left corner (x, y) [m] of the grid; by default the obstacles' bounding box
            grown by `margin`, snapped to a multiple of `resolution`.
        size: (height, width) in cells; by default enough to cover the bounding box + margin.
        margin: [m] of free space around the obstacles in the default extent.

    Returns:
        An OccupancyRaster; ``raster.cells[raster.cell_of(x, y)]`` tells whether (x, y)'s cell
        is occupied.
    """
    if not resolution > 0:
        raise ValueError(f'resolution must be > 0 [m], got {resolution}')
    bounds = world.bounds() or (-margin, -margin, margin, margin)
    if origin is None:
        origin = (math.floor((bounds[0] - margin) / resolution) * resolution,
                  math.floor((bounds[1] - margin) / resolution) * resolution)
    if size is None:
        size = (int(math.ceil((bounds[3] + margin - origin[1]) / resolution)),
                int(math.ceil((bounds[2] + margin - origin[0]) / resolution)))
    geometry = GridGeometry(resolution, origin, size)
    cells = np.zeros(geometry.shape, dtype=bool)

    def grid(xy: np.ndarray) -> np.ndarray:
        """World coordinates (N, 2) -> continuous grid coordinates (N, 2) x, y [cells]."""
        rows, cols = geometry.world_to_cell_continuous(xy[:, 0], xy[:, 1])
        return np.column_stack([cols, rows])

    for shape in world.polygons:
        edges = np.vstack([loop_edges(loop) for loop in shape])
        g = np.hstack([grid(edges[:, :2]), grid(edges[:, 2:])])
        _fill_inside(cells, g)
        _mark_pieces(cells, g, both_sides_on_line=False)
    if len(world.segments):
        g = np.hstack([grid(world.segments[:, :2]), grid(world.segments[:, 2:])])
        _mark_pieces(cells, g, both_sides_on_line=True)
    for cx, cy, r in world.circles:
        row, col = geometry.world_to_cell_continuous(cx, cy)
        _mark_disc(cells, col, row, r / resolution)
    return OccupancyRaster(cells, geometry.origin[:2], geometry.resolution)


def _fill_inside(cells: np.ndarray, edges: np.ndarray) -> None:
    """Mark cells whose centre lies inside the closed loops with these sides (grid units)."""
    height, width = cells.shape
    x1, y1, x2, y2 = edges.T
    lo = max(0, int(math.floor(min(y1.min(), y2.min()))))
    hi = min(height, int(math.ceil(max(y1.max(), y2.max()))) + 1)
    if lo >= hi:
        return
    rows = np.arange(lo, hi)
    cy = rows[:, None] + 0.5
    straddles = (y1[None, :] > cy) != (y2[None, :] > cy)
    row_idx, edge_idx = np.nonzero(straddles)
    if len(row_idx) == 0:
        return
    x_a, y_a, x_b, y_b = x1[edge_idx], y1[edge_idx], x2[edge_idx], y2[edge_idx]
    x_cross = x_a + (cy[row_idx, 0] - y_a) * (x_b - x_a) / (y_b - y_a)
    # A centre at column c (x = c + 0.5) sees this crossing on its right iff c < x_cross - 0.5.
    first_right = np.clip(np.ceil(x_cross - 0.5), 0, width).astype(np.int64)
    toggles = np.zeros((len(rows), width + 1), dtype=np.int64)
    np.add.at(toggles, (row_idx, first_right), 1)
    total = np.bincount(row_idx, minlength=len(rows))
    crossings_right = total[:, None] - np.cumsum(toggles, axis=1)[:, :width]
    cells[lo:hi] |= (crossings_right % 2) == 1


def _mark_pieces(cells: np.ndarray, edges: np.ndarray, *, both_sides_on_line: bool) -> None:
    """Mark the cells whose interior each segment (grid units) passes through."""
    height, width = cells.shape
    x1, y1, x2, y2 = edges.T
    dx, dy = x2 - x1, y2 - y1
    # Parameters t in (0, 1) where each segment crosses a vertical or horizontal grid line.
    params = [np.zeros(len(edges)), np.ones(len(edges))]
    owners = [np.arange(len(edges)), np.arange(len(edges))]
    for start, delta in ((x1, dx), (y1, dy)):
        lo = np.floor(np.minimum(start, start + delta)) + 1
        hi = np.ceil(np.maximum(start, start + delta)) - 1
        counts = np.where(delta != 0, np.maximum(hi - lo + 1, 0), 0).astype(np.int64)
        owner = np.repeat(np.arange(len(edges)), counts)
        offset = np.arange(counts.sum()) - np.repeat(np.cumsum(counts) - counts, counts)
        lines = lo[owner] + offset
        params.append((lines - start[owner]) / delta[owner])
        owners.append(owner)
    owner = np.concatenate(owners)
    t = np.concatenate(params)
    order = np.lexsort((t, owner))
    owner, t = owner[order], t[order]
    same = owner[1:] == owner[:-1]
    seg, t_mid = owner[1:][same], (t[1:][same] + t[:-1][same]) / 2.0
    px, py = x1[seg] + t_mid * dx[seg], y1[seg] + t_mid * dy[seg]
    cols, rows = np.floor(px).astype(np.int64), np.floor(py).astype(np.int64)
    on_x = np.abs(px - np.round(px)) < _ON_LINE
    on_y = np.abs(py - np.round(py)) < _ON_LINE
    keep = ~(on_x | on_y)
    pieces_r, pieces_c = [rows[keep]], [cols[keep]]
    if both_sides_on_line:
        # A segment lying along a grid line touches the cells on both sides of it.
        for on, other in ((on_x & ~on_y, 'x'), (on_y & ~on_x, 'y')):
            if other == 'x':
                line = np.round(px[on]).astype(np.int64)
                pieces_r += [rows[on], rows[on]]
                pieces_c += [line - 1, line]
            else:
                line = np.round(py[on]).astype(np.int64)
                pieces_r += [line - 1, line]
                pieces_c += [cols[on], cols[on]]
    r, c = np.concatenate(pieces_r), np.concatenate(pieces_c)
    inside = (r >= 0) & (r < height) & (c >= 0) & (c < width)
    cells[r[inside], c[inside]] = True


def _mark_disc(cells: np.ndarray, cx: float, cy: float, r: float) -> None:
    """Mark cells whose interior overlaps the disc (grid units)."""
    height, width = cells.shape
    r0, r1 = max(0, int(math.floor(cy - r))), min(height, int(math.ceil(cy + r)) + 1)
    c0, c1 = max(0, int(math.floor(cx - r))), min(width, int(math.ceil(cx + r)) + 1)
    if r0 >= r1 or c0 >= c1:
        return
    rows = np.arange(r0, r1)[:, None]
    cols = np.arange(c0, c1)[None, :]
    near_x = np.clip(cx, cols, cols + 1) - cx
    near_y = np.clip(cy, rows, rows + 1) - cy
    cells[r0:r1, c0:c1] |= near_x ** 2 + near_y ** 2 < r * r
