"""Log-odds occupancy grid, updated by casting every beam of a scan at once.

Each cell holds the sum of the evidence it received, in log-odds: a beam that ends in a cell
adds `hit` (log(p/(1-p)) of the hit probability), a cell a beam passed through adds `miss`
(negative). Within one scan a cell counts once, however many beams cross it, and a cell that
some beam ends in counts as a hit only. The sum is never clamped: the world is assumed static,
and a sum makes a scan's contribution removable (`add_scan(..., weight=-1)`, to float rounding),
which is how the mapper moves scans when the pose graph corrects their poses.

Ray casting, vectorised: every ray from the sensor to an endpoint is sampled every half cell
(all rays together, with `np.repeat`), the samples are floored to cells, and the cells of the
scan are marked in two boolean windows the size of the scan's bounding box (free, hit), so
duplicates cost nothing and the window is added to the grid in one operation.

The grid grows as scans reach beyond it, over a fixed lattice of cells anchored at the world's
origin (`lattice`, a zros.grid_geometry.GridGeometry). Layout as nav_msgs/OccupancyGrid:
`cells[row, col]` covers x in [ox + col * res, ox + (col + 1) * res), row 0 is the lowest y.
"""
from __future__ import annotations

import math

import numpy as np

from zros.grid_geometry import GridGeometry
from zros.map_io import OccupancyMap
from zros.slam.geometry import transform_points
from zros.slam.scan import ScanPoints

__all__ = ['LogOddsGrid', 'log_odds', 'occupancy_from_scans']

#: Grow by at least this much [m] on a side when a scan reaches beyond the grid.
_GROW_MARGIN = 2.0
#: Ray samples per cell length.
_SAMPLES_PER_CELL = 2.0


def log_odds(probability: float) -> float:
    return math.log(probability / (1.0 - probability))


class LogOddsGrid:
    """A growable log-odds occupancy grid (module docstring).

    Args:
        resolution: cell size [m].
        hit_probability: occupancy probability one hit stands for (> 0.5).
        miss_probability: occupancy probability one pass-through stands for (< 0.5).
    """

    def __init__(self, resolution: float, *, hit_probability: float = 0.7, miss_probability: float = 0.3) -> None:
        if not (0.5 < hit_probability < 1.0 and 0.0 < miss_probability < 0.5):
            raise ValueError('need 0.5 < hit_probability < 1 and 0 < miss_probability < 0.5')
        #: The unbounded grid the cells belong to: cell (0, 0)'s corner at the world's origin,
        #: so a cell keeps its index as the array grows.
        self.lattice = GridGeometry(resolution)
        self.hit = log_odds(hit_probability)
        self.miss = log_odds(miss_probability)
        self.cells = np.zeros((0, 0), dtype=np.float32)
        self.offset = (0, 0)            # lattice (row, col) of cells[0, 0]

    @property
    def resolution(self) -> float:
        """Cell size [m]."""
        return self.lattice.resolution

    @property
    def geometry(self) -> GridGeometry:
        """Where `cells` lies in the world."""
        return GridGeometry(self.resolution, self.lattice.cell_corner(*self.offset), self.cells.shape)

    # -- updating ---------------------------------------------------------------------------------
    def add_scan(self, pose: np.ndarray, scan: ScanPoints, *, weight: float = 1.0) -> None:
        """Add the evidence of one scan taken at `pose` (x, y, yaw of the base frame); with
        `weight=-1`, remove what the same call added."""
        origin = self._lattice_cells(transform_points(pose, scan.origin[None, :]))[0]
        ends_hit = self._lattice_cells(transform_points(pose, scan.hits))
        ends_miss = self._lattice_cells(transform_points(pose, scan.misses))
        ends = np.vstack([ends_hit, ends_miss])
        if len(ends) == 0:
            return
        samples = _ray_samples(origin, ends)
        free_cells = np.floor(samples).astype(np.int64)            # (S, 2) row, col
        hit_cells = np.floor(ends_hit).astype(np.int64)
        every = np.vstack([free_cells, hit_cells, np.floor(origin)[None, :].astype(np.int64)])
        lo, hi = every.min(axis=0), every.max(axis=0) + 1           # row, col bounds
        self._ensure(lo, hi)
        shape = (int(hi[0] - lo[0]), int(hi[1] - lo[1]))
        free = np.zeros(shape, dtype=bool)
        free[free_cells[:, 0] - lo[0], free_cells[:, 1] - lo[1]] = True
        hit = np.zeros(shape, dtype=bool)
        hit[hit_cells[:, 0] - lo[0], hit_cells[:, 1] - lo[1]] = True
        update = np.where(hit, self.hit, np.where(free, self.miss, 0.0)).astype(np.float32)
        r0, c0 = int(lo[0] - self.offset[0]), int(lo[1] - self.offset[1])
        window = self.cells[r0:r0 + shape[0], c0:c0 + shape[1]]
        window += update * np.float32(weight)

    def _lattice_cells(self, points: np.ndarray) -> np.ndarray:
        """(N, 2) points x, y [m] -> (N, 2) continuous lattice cells (row, col)."""
        return np.column_stack(self.lattice.world_to_cell_continuous(points[:, 0], points[:, 1]))

    def _ensure(self, lo: np.ndarray, hi: np.ndarray) -> None:
        """Grow the array so that lattice cells rows [lo[0], hi[0]), cols [lo[1], hi[1]) exist."""
        row0, col0 = self.offset
        rows, cols = self.cells.shape
        if rows and lo[0] >= row0 and hi[0] <= row0 + rows and lo[1] >= col0 and hi[1] <= col0 + cols:
            return
        margin = int(math.ceil(_GROW_MARGIN / self.resolution))
        if rows:
            new_row0, new_col0 = min(row0, int(lo[0]) - margin), min(col0, int(lo[1]) - margin)
            new_row1 = max(row0 + rows, int(hi[0]) + margin)
            new_col1 = max(col0 + cols, int(hi[1]) + margin)
        else:
            new_row0, new_col0 = int(lo[0]) - margin, int(lo[1]) - margin
            new_row1, new_col1 = int(hi[0]) + margin, int(hi[1]) + margin
        grown = np.zeros((new_row1 - new_row0, new_col1 - new_col0), dtype=np.float32)
        grown[row0 - new_row0:row0 - new_row0 + rows, col0 - new_col0:col0 - new_col0 + cols] = self.cells
        self.cells, self.offset = grown, (new_row0, new_col0)

    # -- reading ------------------------------------------------------------------------------------
    def observed_bounds(self) -> tuple[int, int, int, int] | None:
        """(row0, row1, col0, col1) array slice of the cells with any evidence, or None."""
        seen = self.cells != 0.0
        rows, cols = np.flatnonzero(seen.any(axis=1)), np.flatnonzero(seen.any(axis=0))
        if len(rows) == 0:
            return None
        return int(rows[0]), int(rows[-1]) + 1, int(cols[0]), int(cols[-1]) + 1

    def occupancy(self, *, occupied_thresh: float = 0.65, free_thresh: float = 0.196,
                  margin: int = 2) -> OccupancyMap:
        """The map as 100 (probability above occupied_thresh), 0 (below free_thresh) and -1
        (unknown, never seen or in between), cropped to the observed cells plus `margin` cells."""
        bounds = self.observed_bounds()
        if bounds is None:
            return OccupancyMap(np.full((1, 1), -1, dtype=np.int8), self.resolution, (0.0, 0.0, 0.0))
        r0, r1, c0, c1 = bounds
        r0, c0 = max(0, r0 - margin), max(0, c0 - margin)
        r1, c1 = min(self.cells.shape[0], r1 + margin), min(self.cells.shape[1], c1 + margin)
        window = self.cells[r0:r1, c0:c1]
        data = np.full(window.shape, -1, dtype=np.int8)
        data[window < log_odds(free_thresh)] = 0
        data[window > log_odds(occupied_thresh)] = 100
        x, y = self.lattice.cell_corner(self.offset[0] + r0, self.offset[1] + c0)
        return OccupancyMap(data, self.resolution, (float(x), float(y), 0.0))

    def clear(self) -> None:
        self.cells = np.zeros((0, 0), dtype=np.float32)
        self.offset = (0, 0)


def _ray_samples(origin: np.ndarray, ends: np.ndarray) -> np.ndarray:
    """Points every half cell along each ray from `origin` to each of `ends` (grid units),
    from the origin up to but not including the end: (S, 2)."""
    delta = ends - origin
    counts = np.maximum(np.ceil(np.hypot(delta[:, 0], delta[:, 1]) * _SAMPLES_PER_CELL), 1).astype(np.int64)
    ray = np.repeat(np.arange(len(ends)), counts)
    step = np.arange(int(counts.sum())) - np.repeat(np.cumsum(counts) - counts, counts)
    t = step / counts[ray]
    return origin + delta[ray] * t[:, None]


def occupancy_from_scans(poses: np.ndarray, scans: list[ScanPoints], resolution: float, *,
                         hit_probability: float = 0.7, miss_probability: float = 0.3,
                         occupied_thresh: float = 0.65, free_thresh: float = 0.196) -> OccupancyMap:
    """One trinary map of `scans` cast at `poses` ((N, 3) in the map frame): a saved graph's map
    drawn from scratch, as merge_maps_kinematic draws its submaps and their merge."""
    grid = LogOddsGrid(resolution, hit_probability=hit_probability, miss_probability=miss_probability)
    for pose, scan in zip(poses, scans):
        grid.add_scan(pose, scan)
    return grid.occupancy(occupied_thresh=occupied_thresh, free_thresh=free_thresh)
