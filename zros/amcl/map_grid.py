"""The map AMCL localizes in: an occupancy grid with its free space and obstacles.

nav_msgs/OccupancyGrid values are 0 (free) .. 100 (occupied), -1 unknown. Nav2's AMCL keeps
only exact 0 as free and exact 100 as occupied, which turns a graded map (Cartographer's, or a
map saved in `scale` mode) into mostly "unknown": no obstacles to match and no free space to
spread particles over. Here the map server's own thresholds decide instead: a cell is free at
or below 25 (free_thresh 0.25) and occupied at or above 65 (occupied_thresh 0.65). A trinary
map (0 / 100 / -1, what map_server publishes by default) reads exactly as in Nav2.

Layout as nav_msgs/OccupancyGrid: `data[row, col]` covers x in [ox + col res, ox + (col+1) res),
y in [oy + row res, ...); row 0 is the lowest y (zros.grid_geometry). The origin's rotation is
ignored, as in Nav2's AMCL: the geometry has yaw 0.
"""
from __future__ import annotations

import numpy as np
from scipy.ndimage import binary_dilation, label

from zros.grid_geometry import GridGeometry, GridGeometryMixin

__all__ = ['MapGrid', 'FREE_MAX', 'OCCUPIED_MIN']

FREE_MAX = 25          # occupancy values 0..FREE_MAX are free space
OCCUPIED_MIN = 65      # occupancy values >= OCCUPIED_MIN are obstacles


class MapGrid(GridGeometryMixin):
    """An occupancy grid, read-only.

    Args:
        data: (height, width) occupancy values, or a flat array with `width` given.
        resolution: cell size [m].
        origin: (x, y) [m] of the lower-left corner of cell (0, 0).
        width: columns, when `data` is flat (an OccupancyGrid's `data`).

    Raises:
        ValueError: a non-positive resolution, a non-finite origin, or data of the wrong size.
    """

    def __init__(self, data: np.ndarray, *, resolution: float, origin: tuple[float, float] = (0.0, 0.0),
                 width: int | None = None) -> None:
        data = np.asarray(data)
        if width is not None:
            if width <= 0 or data.size % width:
                raise ValueError(f'map data of {data.size} cells is not a whole number of rows of {width}')
            data = data.reshape(-1, width)
        if data.ndim != 2 or data.size == 0:
            raise ValueError(f'map data must be a non-empty 2D grid, got shape {data.shape}')
        self.geometry = GridGeometry(resolution, (origin[0], origin[1]), data.shape)
        self.data = data.astype(np.int16)
        self.data.flags.writeable = False
        self.free = (self.data >= 0) & (self.data <= FREE_MAX)
        self.occupied = self.data >= OCCUPIED_MIN
        #: Flat indices of the free cells, for sampling poses in free space.
        self.free_cells = np.flatnonzero(self.free)

    @property
    def origin(self) -> tuple[float, float]:
        """(x, y) [m] of the lower-left corner of cell (0, 0)."""
        return self.geometry.origin[:2]

    def cells(self, x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Cells of points x, y [m] (same shapes): (rows, cols, inside); rows/cols are clipped
        into the grid, so index with them only where `inside`."""
        return self.geometry.world_to_cell_clipped(x, y)

    def is_free(self, x: np.ndarray, y: np.ndarray) -> np.ndarray:
        """Whether each point x, y [m] lies in a free cell of the map: bool, x's shape."""
        rows, cols, inside = self.cells(np.asarray(x, dtype=np.float64), np.asarray(y, dtype=np.float64))
        return inside & self.free[rows, cols]

    def cell_centres(self, flat: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """x, y [m] of the centres of cells given by flat index."""
        return self.geometry.cell_centre(*self.geometry.cell_of_index(flat))

    def sample_free(self, count: int, rng: np.random.Generator, weights: np.ndarray | None = None) -> np.ndarray:
        """`count` poses (count, 3) x, y [m], yaw [rad] in free space: a free cell drawn uniformly
        (or by `weights`, one per entry of `free_cells`), a uniform point inside it, a uniform
        yaw in [-pi, pi). Raises ValueError when the map has no free cell."""
        if len(self.free_cells) == 0:
            raise ValueError('the map has no free cell to put particles in')
        if weights is None:
            picked = self.free_cells[rng.integers(0, len(self.free_cells), count)]
        else:
            cumulative = np.cumsum(weights)
            picked = self.free_cells[np.minimum(np.searchsorted(cumulative, rng.random(count) * cumulative[-1],
                                                                side='right'), len(cumulative) - 1)]
        x, y = self.cell_centres(picked)
        jitter = (rng.random((count, 2)) - 0.5) * self.resolution
        return np.column_stack([x + jitter[:, 0], y + jitter[:, 1], rng.uniform(-np.pi, np.pi, count)])

    def reachable_from(self, x: float, y: float) -> 'MapGrid':
        """What a mapper driving from (x, y) [m] would know of this map: the free space it can
        reach, and the obstacle cells that border it (a lidar never sees inside a wall); all
        else unknown. A simulator's exact raster is free outside the arena and solid inside
        thick walls, and a laser end point that overshoots a wall's surface must not score as
        a hit. ValueError when (x, y) is not in free space."""
        if not self.is_free(np.array([x]), np.array([y]))[0]:
            raise ValueError(f'({x:g}, {y:g}) is not in the map\'s free space')
        regions, _ = label(self.free)
        rows, cols, _ = self.cells(np.array([x]), np.array([y]))
        reachable = regions == regions[rows[0], cols[0]]
        surface = self.occupied & binary_dilation(reachable, structure=np.ones((3, 3), dtype=bool))
        data = np.where(reachable | surface, self.data, -1)
        return MapGrid(data, resolution=self.resolution, origin=self.origin)
