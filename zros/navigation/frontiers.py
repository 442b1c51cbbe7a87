"""Frontier search for exploration (explore_lite's role): where known free space meets the unknown.

A frontier cell is an unknown cell with a free 4-neighbour that the robot can reach through
free space; 8-connected frontier cells form one frontier. explore_lite finds them with a
breadth-first search from the robot; here the same set comes from connected-component labelling
(scipy.ndimage.label), vectorised. The map is thresholded first: a cell is free when its
occupancy is known and below `free_threshold` (SLAM maps carry graded values, on which
explore_lite's exact-zero test stops early).

Each frontier has a size (cells), a centroid, its cell closest to the robot (`middle`) and that
distance; frontiers shorter than `min_frontier_size` [m] are dropped, and the rest are sorted by
explore_lite's cost: potential_scale * min_distance * resolution - gain_scale * size * resolution
(lowest first; min_distance in metres, as explore_lite computes it).
Reference: robo-friends/m-explore-ros2 explore/src/frontier_search.cpp, explore.cpp.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import ndimage

__all__ = ['Frontier', 'find_frontiers', 'Blacklist']

_ROBOT_SEARCH_M = 0.5     # [m] how far from the robot its free space may start
_FOUR = ndimage.generate_binary_structure(2, 1)
_EIGHT = ndimage.generate_binary_structure(2, 2)


@dataclass
class Frontier:
    size: int                           # [cells]
    centroid: tuple[float, float]       # [m], map frame
    goal: tuple[float, float]           # [m] the frontier cell nearest the centroid: on the frontier,
                                        # where a centroid (of a ring-shaped frontier) may be in a wall
    middle: tuple[float, float]         # [m] the frontier cell closest to the robot
    min_distance: float                 # [m] from the robot to `middle`
    cost: float
    points: np.ndarray                  # (size, 2) [m] the cells' centres


def find_frontiers(occupancy: np.ndarray, resolution: float, origin: tuple[float, float],
                   robot_xy: tuple[float, float], *, min_frontier_size: float = 0.5, potential_scale: float = 1e-3,
                   gain_scale: float = 1.0, free_threshold: int = 25) -> list[Frontier] | None:
    """Frontiers of `occupancy` ((H, W) OccupancyGrid values, row 0 = lowest y) reachable from
    `robot_xy` [m], cheapest first; None when the map has no free space near the robot yet (a
    map made before the first scan), which is not the same as nothing left to explore."""
    occ = np.asarray(occupancy, np.int16)
    unknown = occ < 0
    free = (occ >= 0) & (occ < free_threshold)
    origin = np.asarray(origin, np.float64)
    rows, cols = occ.shape
    rc = np.floor((np.asarray(robot_xy) - origin) / resolution).astype(int)[::-1]
    if not (0 <= rc[0] < rows and 0 <= rc[1] < cols):
        return None
    labels, _ = ndimage.label(free, structure=_FOUR)
    start = labels[rc[0], rc[1]]
    if start == 0:
        # The robot's own cell is not free (a graded cell, or not mapped yet): the nearest free cell.
        idx = np.argwhere(free)
        near = np.hypot(idx[:, 0] - rc[0], idx[:, 1] - rc[1]) if len(idx) else np.zeros(0)
        if len(idx) == 0 or near.min() * resolution > _ROBOT_SEARCH_M:
            return None
        nearest = idx[np.argmin(near)]
        start = labels[nearest[0], nearest[1]]
    reachable = labels == start
    frontier_cells = unknown & ndimage.binary_dilation(reachable, structure=_FOUR)
    groups, count = ndimage.label(frontier_cells, structure=_EIGHT)
    if count == 0:
        return []
    rr, cc = np.nonzero(groups)
    group = groups[rr, cc]
    centres = np.stack([cc, rr], axis=1) * resolution + origin + resolution / 2
    dist = np.hypot(centres[:, 0] - robot_xy[0], centres[:, 1] - robot_xy[1])
    order = np.argsort(group, kind='stable')
    group, centres, dist = group[order], centres[order], dist[order]
    bounds = np.searchsorted(group, np.arange(1, count + 2))
    frontiers = []
    for k in range(count):
        a, b = bounds[k], bounds[k + 1]
        size = b - a
        if size * resolution < min_frontier_size:
            continue
        pts = centres[a:b]
        i = int(np.argmin(dist[a:b]))
        cost = potential_scale * float(dist[a + i]) * resolution - gain_scale * size * resolution
        centroid = pts.mean(axis=0)
        goal = pts[int(np.argmin(np.hypot(pts[:, 0] - centroid[0], pts[:, 1] - centroid[1])))]
        frontiers.append(Frontier(int(size), tuple(centroid), tuple(goal), tuple(pts[i]), float(dist[a + i]), cost, pts))
    frontiers.sort(key=lambda f: f.cost)
    return frontiers


class Blacklist:
    """Goals given up on; a point within `radius_cells` cells (in x and y) of one is blacklisted."""

    def __init__(self, resolution: float, radius_cells: int = 5) -> None:
        self.tolerance = radius_cells * resolution
        self.points: list[tuple[float, float]] = []

    def add(self, xy: tuple[float, float]) -> None:
        self.points.append((float(xy[0]), float(xy[1])))

    def contains(self, xy: tuple[float, float]) -> bool:
        if not self.points:
            return False
        p = np.asarray(self.points)
        return bool(((np.abs(p[:, 0] - xy[0]) < self.tolerance) & (np.abs(p[:, 1] - xy[1]) < self.tolerance)).any())
