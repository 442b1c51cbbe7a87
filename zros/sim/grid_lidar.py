"""A planar lidar that sees an occupancy grid (a map) instead of a world's shapes.

Nav2's loopback simulator has no world, only the map server's map, yet the collision monitor and
the costmaps' obstacle layers want a /scan. Rather than a second ray marcher over cells, the
grid's occupied regions are turned once into their outlines, straight wall segments along the
cell borders (neighbouring borders on one grid line merged into one segment), and the scan is
cast against those with the simulator's own `cast_fan`: one ray caster in zros, exact distances
to the cell borders, and the cost per scan of a few hundred segments, not of the map's size.

A cell is an obstacle when its value is at least `occupied_threshold` (Nav2's loopback simulator
uses 60 on the 0..100 scale); unknown (-1) cells and everything outside the grid are free, so a
beam that leaves the map reports nothing, and a sensor outside the map sees nothing at all.
"""
from __future__ import annotations

import math

import numpy as np

from zros.grid_geometry import GridGeometry
from zros.sim.raycast import cast_fan

__all__ = ['occupied_outline', 'GridLidar', 'OCCUPIED_THRESHOLD']

#: Occupancy (0..100) from which Nav2's loopback simulator reflects a beam.
OCCUPIED_THRESHOLD = 60

_NO_CIRCLES = np.empty((0, 3))


def _runs(mask: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Maximal runs of True along axis 1: (line, first, end) with `end` one past the last."""
    padded = np.zeros((mask.shape[0], mask.shape[1] + 2), dtype=np.int8)
    padded[:, 1:-1] = mask
    step = np.diff(padded, axis=1)
    starts, ends = np.nonzero(step == 1), np.nonzero(step == -1)
    # np.nonzero walks row-major, so the k-th start and k-th end of a line belong together.
    return starts[0], starts[1], ends[1]


def occupied_outline(occupied: np.ndarray, geometry: GridGeometry) -> np.ndarray:
    """The borders between obstacle cells and the rest, as world segments.

    Args:
        occupied: (rows, cols) bool, True for an obstacle cell (row 0 is the lowest y).
        geometry: where the grid lies; its shape must be `occupied`'s.

    Returns:
        (N, 4) float64 segments `x1, y1, x2, y2` [m], one per maximal straight run of border.

    Raises:
        ValueError: `occupied` is not 2-D or does not match the geometry's shape.
    """
    occupied = np.asarray(occupied, dtype=bool)
    if occupied.ndim != 2 or occupied.shape != tuple(geometry.shape):
        raise ValueError(f'occupancy of shape {occupied.shape} does not match the grid {tuple(geometry.shape)}')
    padded = np.pad(occupied, 1)
    # Horizontal borders lie on grid line y = row (0..rows), between rows row - 1 and row.
    along_x = padded[1:, 1:-1] != padded[:-1, 1:-1]
    # Vertical borders lie on grid line x = col (0..cols), between cols col - 1 and col.
    along_y = padded[1:-1, 1:] != padded[1:-1, :-1]
    row, first, end = _runs(along_x)
    col, low, high = _runs(along_y.T)
    x1, y1 = geometry.cell_corner(np.concatenate([row, low]), np.concatenate([first, col]))
    x2, y2 = geometry.cell_corner(np.concatenate([row, high]), np.concatenate([end, col]))
    return np.stack([x1, y1, x2, y2], axis=1).astype(np.float64)


class GridLidar:
    """Scans of one occupancy grid from any sensor pose.

    Args:
        occupancy: (rows, cols) occupancy values (nav_msgs/OccupancyGrid's, -1 unknown).
        geometry: where the grid lies.
        occupied_threshold: values from this up reflect a beam.

    Raises:
        ValueError: as `occupied_outline`.
    """

    def __init__(self, occupancy: np.ndarray, geometry: GridGeometry, *,
                 occupied_threshold: int = OCCUPIED_THRESHOLD) -> None:
        self.geometry = geometry
        self.edges = occupied_outline(np.asarray(occupancy) >= occupied_threshold, geometry)

    def inside(self, x: float, y: float) -> bool:
        """Whether the point (x, y) [m] lies on the grid."""
        rows, cols = self.geometry.world_to_cell(np.array([x]), np.array([y]))
        return bool(self.geometry.contains(rows, cols)[0])

    def scan(self, pose: tuple[float, float, float], angle_min: float, angle_increment: float, count: int,
             range_max: float) -> np.ndarray:
        """(count,) float64 ranges [m] from a sensor at (x, y, yaw) [m, rad] in the grid's frame;
        beam k at `yaw + angle_min + k * angle_increment`; ``inf`` where nothing is hit within
        `range_max`, and for every beam when the sensor is off the grid."""
        x, y, yaw = (float(v) for v in pose)
        if count <= 0:
            return np.empty(0)
        if not self.inside(x, y) or not len(self.edges):
            return np.full(count, math.inf)
        return cast_fan((x, y), yaw + angle_min, angle_increment, count, self.edges, _NO_CIRCLES, range_max)
