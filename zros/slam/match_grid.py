"""The grid a scan is matched against: a likelihood field of reference points, at several
resolutions.

Level 0 is the likelihood field: each cell holds exp(-d² / 2σ²), d being the distance [m] from
the cell's centre to the nearest reference point, so a scan point scores 1 on a known surface
and fades to 0 a few σ away from it. Matching maximises the mean score of the scan's points.
The distance is measured to the points themselves, not to the centres of the cells they fall
in: scipy's Euclidean distance transform finds each cell's nearest occupied cell, and the
distance is taken to the mean of that cell's points. Rounding to cell centres would shift a
straight wall by up to half a cell, the same way for all its points, and bias the match.

Level k (k >= 1) holds, in cell (r, c), the maximum of level 0 over the 2^k x 2^k block of cells
starting at (r, c). A candidate that stands for every translation in such a block therefore
scores at level k no less than any of those translations scores at level 0: an upper bound,
which is what lets the correlative search prune whole blocks (Olson, "Real-time correlative
scan matching", ICRA 2009; Hess et al., "Real-time loop closure in 2D LIDAR SLAM", ICRA 2016).
"""
from __future__ import annotations

import numpy as np
from scipy import ndimage
from scipy.spatial import cKDTree

from zros.grid_geometry import GridGeometry, GridGeometryMixin

__all__ = ['MatchGrid']

#: Reference points fitted together into one local line.
_NEIGHBOURS = 8


class MatchGrid(GridGeometryMixin):
    """Likelihood field of `points` and its max-pooled levels.

    Args:
        points: (N, 2) reference points [m] (scan endpoints in the map frame), N >= 1.
        resolution: cell size [m] of level 0.
        sigma: spread [m] of the likelihood around each point.
        levels: number of levels (1 = the field only).
        margin: free space [m] around the points' bounding box.
    """

    def __init__(self, points: np.ndarray, resolution: float, *, sigma: float = 0.05, levels: int = 6,
                 margin: float = 0.5) -> None:
        points = np.asarray(points, dtype=np.float64)
        if points.ndim != 2 or len(points) == 0:
            raise ValueError('a MatchGrid needs at least one reference point')
        lo = np.floor((points.min(axis=0) - margin) / resolution) * resolution
        hi = points.max(axis=0) + margin
        cols, rows = (np.ceil((hi - lo) / resolution)).astype(int) + 1
        #: Where level 0's cells lie; level k's cell (r, c) starts at level 0's (r, c).
        self.geometry = GridGeometry(resolution, (lo[0], lo[1]), (rows, cols))
        flat = self.geometry.index(*self.geometry.world_to_cell(points[:, 0], points[:, 1]))
        counts = np.bincount(flat, minlength=rows * cols).reshape(rows, cols)
        mean_x = np.bincount(flat, points[:, 0], minlength=rows * cols).reshape(rows, cols)
        mean_y = np.bincount(flat, points[:, 1], minlength=rows * cols).reshape(rows, cols)
        occupied = counts > 0
        mean_x[occupied] /= counts[occupied]
        mean_y[occupied] /= counts[occupied]
        nearest_row, nearest_col = ndimage.distance_transform_edt(~occupied, return_distances=False,
                                                                  return_indices=True)
        centre_x, centre_y = self.geometry.centres()
        distance = np.hypot(centre_x - mean_x[nearest_row, nearest_col], centre_y - mean_y[nearest_row, nearest_col])
        field = np.exp(-0.5 * (distance / sigma) ** 2).astype(np.float32)
        self.levels = [field]
        for k in range(1, levels):
            self.levels.append(_block_max(self.levels[-1], 1 << (k - 1)))
        self.points = points
        self._surfaces: tuple[cKDTree, np.ndarray, np.ndarray, np.ndarray] | None = None

    def surfaces(self) -> tuple[cKDTree, np.ndarray, np.ndarray, np.ndarray]:
        """The reference points as local line segments, for point-to-line refinement: a KD-tree
        of the points, and per point the centroid (N, 2) and unit normal (N, 2) of its
        `_NEIGHBOURS` nearest points, and how line-like they are (N,), 1 for a straight wall,
        0 for a round blob. Made on first use."""
        if self._surfaces is None:
            tree = cKDTree(self.points)
            k = min(_NEIGHBOURS, len(self.points))
            _, neighbours = tree.query(self.points, k=k)
            near = self.points[neighbours.reshape(len(self.points), k)]          # (N, k, 2)
            centroid = near.mean(axis=1)
            spread = near - centroid[:, None, :]
            cov = np.einsum('nki,nkj->nij', spread, spread) / k
            eigenvalues, eigenvectors = np.linalg.eigh(cov)                   # ascending
            normal = eigenvectors[:, :, 0]
            linear = 1.0 - eigenvalues[:, 0] / np.maximum(eigenvalues[:, 1], 1e-12)
            self._surfaces = (tree, centroid, normal, np.clip(linear, 0.0, 1.0))
        return self._surfaces

    def lookup(self, level: int, rows: np.ndarray, cols: np.ndarray) -> np.ndarray:
        """Level values at integer cells (any shape); 0 outside the grid."""
        inside = self.geometry.contains(rows, cols)
        flat = np.where(inside, self.geometry.index(rows, cols), 0)
        return np.where(inside, self.levels[level].ravel()[flat], np.float32(0.0))

    def interpolate(self, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Bilinear value of level 0 at (N, 2) points [m], and its gradient (N, 2) [1/m]."""
        rows, cols = self.geometry.world_to_cell_continuous(points[:, 0], points[:, 1])
        rows, cols = rows - 0.5, cols - 0.5                         # cell centres at integers
        row, col = np.floor(rows).astype(np.int64), np.floor(cols).astype(np.int64)
        fy, fx = rows - row, cols - col
        v00 = self.lookup(0, row, col)
        v01 = self.lookup(0, row, col + 1)
        v10 = self.lookup(0, row + 1, col)
        v11 = self.lookup(0, row + 1, col + 1)
        value = (v00 * (1 - fx) * (1 - fy) + v01 * fx * (1 - fy) + v10 * (1 - fx) * fy + v11 * fx * fy)
        dx = ((v01 - v00) * (1 - fy) + (v11 - v10) * fy) / self.resolution
        dy = ((v10 - v00) * (1 - fx) + (v11 - v01) * fx) / self.resolution
        return value, np.stack([dx, dy], axis=1)


def _block_max(grid: np.ndarray, half: int) -> np.ndarray:
    """Cell (r, c) = max of `grid` over (r..r+2h-1, c..c+2h-1), given that `grid` already holds
    the max over h x h blocks (outside the grid counts as 0)."""
    padded = np.zeros((grid.shape[0] + half, grid.shape[1] + half), dtype=grid.dtype)
    padded[:grid.shape[0], :grid.shape[1]] = grid
    rows, cols = grid.shape
    return np.maximum(np.maximum(padded[:rows, :cols], padded[half:half + rows, :cols]),
                      np.maximum(padded[:rows, half:half + cols], padded[half:half + rows, half:half + cols]))

