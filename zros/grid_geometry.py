"""Where the cells of an occupancy grid lie in the world: one value type for every grid in zros.

The map server's map, AMCL's map, the simulator's ground truth, the SLAM grids and the costmaps
all place cells the same way, so the arithmetic lives here once, under the names Nav2's
Costmap2D gives it (`worldToMap` -> `world_to_cell`, `mapToWorld` -> `cell_centre`,
`worldToMapContinuous` -> `world_to_cell_continuous`, `worldToMapEnforceBounds` ->
`world_to_cell_clipped`); grid bugs (a swapped index, a missing half cell) are fixed here or
nowhere.

Conventions, as nav_msgs/OccupancyGrid defines them:

- Index order is (row, col) = (y, x) everywhere: `data[row, col]`, row-major from the origin,
  row 0 the lowest y. Every method takes and returns rows before cols.
- `origin` is the pose (x [m], y [m], yaw [rad]) of the grid's corner, the lower-left corner of
  cell (0, 0), in the grid's frame. Cell (row, col) covers [col, col + 1) x [row, row + 1) in
  grid units, and its centre is half a cell in from that corner.
- The yaw is honoured: a grid whose origin is rotated has its rows along the rotated y axis.
  Nav2's costmaps and AMCL ignore a map's origin yaw; the grids here that do the same build
  their geometry with yaw 0 and say so.

Every conversion is vectorised: arrays of any (equal) shape in, arrays of that shape out.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ['GridGeometry', 'GridGeometryMixin']


@dataclass(frozen=True, slots=True)
class GridGeometry:
    """The placement of a (rows, cols) grid of square cells in the world (module docstring).

    Args:
        resolution: cell side [m], finite and > 0.
        origin: (x [m], y [m], yaw [rad]) of cell (0, 0)'s lower-left corner; (x, y) means yaw 0.
        shape: (rows, cols) = (height, width) [cells], each >= 0.

    Raises:
        ValueError: a resolution that is not finite and > 0, an origin that is not 2 or 3 finite
            numbers, or a negative size.
    """
    resolution: float
    origin: tuple[float, float, float] = (0.0, 0.0, 0.0)
    shape: tuple[int, int] = (0, 0)

    def __post_init__(self) -> None:
        resolution = float(self.resolution)
        if not (math.isfinite(resolution) and resolution > 0):
            raise ValueError(f'grid resolution must be > 0 [m], got {self.resolution}')
        origin = tuple(float(v) for v in self.origin)
        if len(origin) not in (2, 3) or not all(math.isfinite(v) for v in origin):
            raise ValueError(f'grid origin must be finite (x, y[, yaw]), got {tuple(self.origin)}')
        shape = tuple(int(n) for n in self.shape)
        if len(shape) != 2 or min(shape) < 0:
            raise ValueError(f'grid shape must be (rows, cols) >= 0, got {tuple(self.shape)}')
        # Normalised in place: the dataclass is frozen to its users, not to its own constructor.
        object.__setattr__(self, 'resolution', resolution)
        object.__setattr__(self, 'origin', origin if len(origin) == 3 else (*origin, 0.0))
        object.__setattr__(self, 'shape', shape)

    @property
    def height(self) -> int:
        """Rows [cells]."""
        return self.shape[0]

    @property
    def width(self) -> int:
        """Columns [cells]."""
        return self.shape[1]

    # -- world -> grid ---------------------------------------------------------------------------
    def world_to_cell_continuous(self, x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Continuous grid coordinates (rows, cols) [cells] of points (x, y) [m]: cell (r, c)
        covers [r, r + 1) x [c, c + 1), so its centre is at (r + 0.5, c + 0.5)."""
        dx, dy = np.subtract(x, self.origin[0]), np.subtract(y, self.origin[1])
        yaw = self.origin[2]
        if yaw != 0.0:
            cos, sin = math.cos(yaw), math.sin(yaw)
            dx, dy = cos * dx + sin * dy, cos * dy - sin * dx
        return dy / self.resolution, dx / self.resolution

    def world_to_cell(self, x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Cells (rows, cols), int64, containing points (x, y) [m]; not bounded by the grid
        (test with `contains`)."""
        rows, cols = self.world_to_cell_continuous(x, y)
        return np.floor(rows).astype(np.int64), np.floor(cols).astype(np.int64)

    def world_to_cell_clipped(self, x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(rows, cols, inside): the cells of points (x, y) [m] clipped into the grid, so that
        they always index it, and whether each point lies in the grid. Needs a non-empty grid."""
        rows, cols = self.world_to_cell(x, y)
        inside = self.contains(rows, cols)
        return np.clip(rows, 0, self.height - 1), np.clip(cols, 0, self.width - 1), inside

    def contains(self, rows: np.ndarray, cols: np.ndarray) -> np.ndarray:
        """Whether each integer cell (rows, cols) is in the grid: bool, the inputs' shape."""
        return (rows >= 0) & (rows < self.height) & (cols >= 0) & (cols < self.width)

    # -- grid -> world ---------------------------------------------------------------------------
    def cell_corner(self, rows: np.ndarray, cols: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(x, y) [m] of the lower-left corners of cells (rows, cols); integer or continuous
        cells, as `world_to_cell_continuous` gives (it is that function's inverse)."""
        u, v = np.multiply(cols, self.resolution), np.multiply(rows, self.resolution)
        yaw = self.origin[2]
        if yaw != 0.0:
            cos, sin = math.cos(yaw), math.sin(yaw)
            u, v = cos * u - sin * v, sin * u + cos * v
        return self.origin[0] + u, self.origin[1] + v

    def cell_centre(self, rows: np.ndarray, cols: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(x, y) [m] of the centres of cells (rows, cols) (Nav2's mapToWorld: half a cell in
        from the corner)."""
        return self.cell_corner(np.add(rows, 0.5), np.add(cols, 0.5))

    def centres(self) -> tuple[np.ndarray, np.ndarray]:
        """(x, y) [m] of every cell's centre: two (rows, cols) arrays."""
        rows, cols = np.meshgrid(np.arange(self.height), np.arange(self.width), indexing='ij')
        return self.cell_centre(rows, cols)

    # -- flat indices ----------------------------------------------------------------------------
    def index(self, rows: np.ndarray, cols: np.ndarray) -> np.ndarray:
        """Row-major flat indices of cells (rows, cols), as into OccupancyGrid `data`."""
        return np.multiply(rows, self.width) + cols

    def cell_of_index(self, flat: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(rows, cols) of row-major flat indices: the inverse of `index`."""
        return np.divmod(flat, self.width)


class GridGeometryMixin:
    """The size and cell size of a grid class that holds its placement as `geometry`, read from
    it so that the two never disagree."""
    geometry: GridGeometry

    @property
    def resolution(self) -> float:
        """Cell size [m]."""
        return self.geometry.resolution

    @property
    def shape(self) -> tuple[int, int]:
        """(rows, cols) [cells]."""
        return self.geometry.shape

    @property
    def height(self) -> int:
        """Rows [cells]."""
        return self.geometry.height

    @property
    def width(self) -> int:
        """Columns [cells]."""
        return self.geometry.width
