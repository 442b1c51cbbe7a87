"""How good a SLAM run is, against the simulator's ground truth (for benchmarks and tests).

It lives with the simulator, whose truth it reads, so that zros.slam stays free of it.

- Trajectory: absolute trajectory error (ATE), the RMSE of the position error of every pose,
  with the estimate and the truth in the same frame: no alignment is fitted, the map frame's
  place in the world is known (where the robot started), so an error at the start counts.
- Map: against the world's exact raster (zros.sim.rasterize). The true wall cells are the
  occupied cells the lidar's rays met, cast without noise from the true poses (so a wall the
  robot never saw does not count against the map); a wall cell is found when the map marks a
  cell within one cell of it occupied. False occupied cells are map cells marked occupied whose
  centre lies in free space in truth (no tolerance); `false_occupied_beyond_one_cell` counts
  only those with no true obstacle within one cell either, the same tolerance the wall recall
  gives. Why both: a wall face that lies on a grid line (the house's 0.15 m walls do) is made
  two cells thick by any lidar map, the 1 cm range noise putting about half the returns in the
  free cell in front of it; a map from the true poses scores 6.7 % on the strict count in
  turtlebot3_house and 0 on the tolerant one (benchmarks/slam.py prints both floors).
- Pose graph edges: `edge_errors` says how far each edge's measurement (a loop closure, a link)
  is from the true relative pose of its two nodes, which tells a false closure (aliasing between
  look-alike rooms: decimetres off) from a right one that is weighted wrongly (centimetres off).
"""
from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from scipy import ndimage

from zros.map_io import OccupancyMap
from zros.rotations import wrap_angle
from zros.sim.raster import OccupancyRaster, rasterize
from zros.sim.world import World
from zros.slam.geometry import compose, inverse, relative, transform_points

__all__ = ['TrajectoryError', 'MapQuality', 'trajectory_error', 'edge_errors', 'in_map_frame', 'map_quality', 'seen_walls',
           'ground_truth_map', 'overlay', 'OVERLAY_COLOURS']


class TrajectoryError(NamedTuple):
    rmse: float                 # [m]
    maximum: float              # [m]
    final: float                # [m] position error of the last pose
    final_heading: float        # [rad] |heading error| of the last pose


class MapQuality(NamedTuple):
    wall_recall: float          # share of visible true wall cells with an occupied map cell within one cell
    false_occupied: float       # share of occupied map cells that are free in truth
    wall_cells: int
    occupied_cells: int
    false_occupied_beyond_one_cell: float = math.nan    # ... with no true obstacle within one cell


def trajectory_error(estimate: np.ndarray, truth: np.ndarray) -> TrajectoryError:
    """ATE of (N, 3) estimated poses against (N, 3) true poses, both in one frame."""
    estimate, truth = np.asarray(estimate, dtype=np.float64), np.asarray(truth, dtype=np.float64)
    error = np.hypot(estimate[:, 0] - truth[:, 0], estimate[:, 1] - truth[:, 1])
    return TrajectoryError(float(np.sqrt(np.mean(error ** 2))), float(error.max()), float(error[-1]),
                           float(abs(wrap_angle(estimate[-1, 2] - truth[-1, 2]))))


def edge_errors(i: np.ndarray, j: np.ndarray, measurement: np.ndarray, truth: np.ndarray) -> np.ndarray:
    """(E, 2) translation [m] and |yaw| [rad] error of edges "node j seen from node i is at
    `measurement` (E, 3)" against the true relative poses, `truth` (N, 3) being the nodes' true
    poses in one frame."""
    truth = np.asarray(truth, dtype=np.float64)
    error = relative(relative(truth[i], truth[j]), np.asarray(measurement, dtype=np.float64).reshape(-1, 3))
    return np.column_stack([np.hypot(error[:, 0], error[:, 1]), np.abs(wrap_angle(error[:, 2]))])


def in_map_frame(truth_world: np.ndarray, map_in_world: np.ndarray) -> np.ndarray:
    """World poses (N, 3) expressed in a map frame placed at `map_in_world`."""
    return relative(np.asarray(map_in_world, dtype=np.float64), np.asarray(truth_world, dtype=np.float64))


def seen_walls(truth: OccupancyRaster, endpoints: np.ndarray) -> np.ndarray:
    """(H, W) bool: the true occupied cells containing any of the (N, 2) world points [m] (the
    ends of noise-free lidar rays, nudged a millimetre into what they hit)."""
    rows = np.floor((endpoints[:, 1] - truth.origin[1]) / truth.resolution).astype(np.int64)
    cols = np.floor((endpoints[:, 0] - truth.origin[0]) / truth.resolution).astype(np.int64)
    inside = (rows >= 0) & (rows < truth.height) & (cols >= 0) & (cols < truth.width)
    seen = np.zeros(truth.cells.shape, dtype=bool)
    seen[rows[inside], cols[inside]] = True
    return seen & truth.cells


def map_quality(grid: OccupancyMap, map_in_world: np.ndarray, truth: OccupancyRaster,
                walls: np.ndarray) -> MapQuality:
    """Compare an occupancy map (in a map frame placed at `map_in_world` (x, y, yaw)) with the
    truth raster, `walls` being the true wall cells to find (seen_walls) (module docstring)."""
    occupied = grid.data >= 100
    wall_rows, wall_cols = np.nonzero(walls)
    res_t = truth.resolution
    wall_world = np.column_stack([truth.origin[0] + (wall_cols + 0.5) * res_t,
                                  truth.origin[1] + (wall_rows + 0.5) * res_t])
    to_map = _inverse_pose(map_in_world, grid.origin)
    near = ndimage.binary_dilation(occupied, structure=np.ones((3, 3), dtype=bool))
    found = _sample(near, transform_points(to_map, wall_world), grid.resolution)
    rows, cols, truly_occupied = _occupied_in_truth(grid, map_in_world, truth)
    inside = (rows >= 0) & (rows < truth.height) & (cols >= 0) & (cols < truth.width)
    near_truth = np.zeros(len(rows), dtype=bool)
    near_truth[inside] = ndimage.binary_dilation(truth.cells, structure=np.ones((3, 3), dtype=bool))[
        rows[inside], cols[inside]]
    wall_count, occ_count = int(walls.sum()), int(occupied.sum())
    return MapQuality(float(found.mean()) if wall_count else math.nan,
                      float((~truly_occupied).mean()) if occ_count else 0.0, wall_count, occ_count,
                      float((~near_truth).mean()) if occ_count else 0.0)


#: RGB of each class in `overlay`'s picture, in the order they are painted (later wins).
OVERLAY_COLOURS = {
    'unknown': (205, 205, 205),         # the map knows nothing here (map_saver's grey)
    'free': (255, 255, 255),            # the map says free
    'truth_obstacle': (170, 200, 240),  # occupied in truth, not a seen wall (inside walls, unseen sides)
    'wall_missed': (30, 90, 230),       # a seen true wall cell with no occupied map cell within one cell
    'wall_found': (0, 0, 0),            # a seen true wall cell the map found
    'false_occupied': (230, 20, 20),    # an occupied map cell whose centre is free in truth
}


def overlay(grid: OccupancyMap, map_in_world: np.ndarray, truth: OccupancyRaster, walls: np.ndarray, *,
            scale: int = 2) -> np.ndarray:
    """A picture of what map_quality counts, on the truth raster's cells: (H*scale, W*scale, 3)
    uint8 RGB, north up (row 0 at the top), colours OVERLAY_COLOURS. Each truth cell shows the
    map cell its centre falls in (free, unknown), then the true obstacles, the seen walls found
    or missed, and in red the map's false occupied cells where map_quality puts them. It is
    the picture to look at before believing (or doubting) the two numbers."""
    occupied = grid.data >= 100
    rows, cols = np.indices(truth.cells.shape)
    centres = np.column_stack([truth.origin[0] + (cols.ravel() + 0.5) * truth.resolution,
                               truth.origin[1] + (rows.ravel() + 0.5) * truth.resolution])
    in_grid = transform_points(_inverse_pose(map_in_world, grid.origin), centres)
    known = _sample(grid.data >= 0, in_grid, grid.resolution).reshape(truth.cells.shape)
    near = ndimage.binary_dilation(occupied, structure=np.ones((3, 3), dtype=bool))
    found = _sample(near, in_grid, grid.resolution).reshape(truth.cells.shape)
    false_rows, false_cols = _false_occupied_cells(grid, map_in_world, truth)
    image = np.empty((*truth.cells.shape, 3), dtype=np.uint8)
    image[:] = OVERLAY_COLOURS['unknown']
    image[known & (_sample(grid.data == 0, in_grid, grid.resolution).reshape(known.shape))] = OVERLAY_COLOURS['free']
    image[truth.cells] = OVERLAY_COLOURS['truth_obstacle']
    image[walls & ~found] = OVERLAY_COLOURS['wall_missed']
    image[walls & found] = OVERLAY_COLOURS['wall_found']
    image[false_rows, false_cols] = OVERLAY_COLOURS['false_occupied']
    return np.repeat(np.repeat(image[::-1], scale, axis=0), scale, axis=1)


def _occupied_in_truth(grid: OccupancyMap, map_in_world: np.ndarray, truth: OccupancyRaster
                       ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """For each occupied map cell (in np.nonzero order): the truth (row, col) its centre falls
    in (may lie outside the raster) and whether that truth cell is occupied."""
    occ_rows, occ_cols = np.nonzero(grid.data >= 100)
    occ_grid = np.column_stack([(occ_cols + 0.5) * grid.resolution, (occ_rows + 0.5) * grid.resolution])
    occ_world = transform_points(_compose_origin(map_in_world, grid.origin), occ_grid)
    rows = np.floor((occ_world[:, 1] - truth.origin[1]) / truth.resolution).astype(np.int64)
    cols = np.floor((occ_world[:, 0] - truth.origin[0]) / truth.resolution).astype(np.int64)
    inside = (rows >= 0) & (rows < truth.height) & (cols >= 0) & (cols < truth.width)
    occupied = np.zeros(len(occ_world), dtype=bool)
    occupied[inside] = truth.cells[rows[inside], cols[inside]]
    return rows, cols, occupied


def _false_occupied_cells(grid: OccupancyMap, map_in_world: np.ndarray, truth: OccupancyRaster
                          ) -> tuple[np.ndarray, np.ndarray]:
    """Truth (rows, cols) of the occupied map cells map_quality counts as false, inside the raster."""
    rows, cols, occupied = _occupied_in_truth(grid, map_in_world, truth)
    inside = (rows >= 0) & (rows < truth.height) & (cols >= 0) & (cols < truth.width)
    return rows[inside & ~occupied], cols[inside & ~occupied]


def _compose_origin(map_in_world: np.ndarray, origin: tuple[float, float, float]) -> np.ndarray:
    """The pose of the grid's cell (0, 0) corner frame in the world."""
    return compose(np.asarray(map_in_world, dtype=np.float64), np.asarray(origin, dtype=np.float64))


def _inverse_pose(map_in_world: np.ndarray, origin: tuple[float, float, float]) -> np.ndarray:
    return inverse(_compose_origin(map_in_world, origin))


def _sample(mask: np.ndarray, points: np.ndarray, resolution: float) -> np.ndarray:
    """mask values at (N, 2) points given in the grid's corner frame [m]; False outside."""
    rows = np.floor(points[:, 1] / resolution).astype(np.int64)
    cols = np.floor(points[:, 0] / resolution).astype(np.int64)
    inside = (rows >= 0) & (rows < mask.shape[0]) & (cols >= 0) & (cols < mask.shape[1])
    out = np.zeros(len(points), dtype=bool)
    out[inside] = mask[rows[inside], cols[inside]]
    return out


def ground_truth_map(world: World, resolution: float = 0.05, *, start: tuple[float, float] | None = None,
                     margin: int = 3) -> OccupancyMap:
    """The map a perfect SLAM run would make of `world`, in the world frame: the free cells
    connected to `start` (default: the world's spawn point) 0, the obstacle cells touching them
    (walls as the lidar sees them, one cell thick) 100, everything else (outside the arena,
    inside pillars) -1; cropped to those cells plus `margin`. What the shipped
    turtlebot3_navigation2/map/map.yaml is made of."""
    raster = rasterize(world, resolution, margin=(margin + 2) * resolution)
    start = (world.spawn.x, world.spawn.y) if start is None else start
    row, col = raster.cell_of(*start)
    if not (0 <= row < raster.height and 0 <= col < raster.width) or raster.cells[row, col]:
        raise ValueError(f'start {start} is not in free space of {world.name}')
    labels, _ = ndimage.label(~raster.cells)
    free = labels == labels[row, col]
    walls = raster.cells & ndimage.binary_dilation(free, structure=np.ones((3, 3), dtype=bool))
    data = np.full(raster.cells.shape, -1, dtype=np.int8)
    data[free], data[walls] = 0, 100
    rows, cols = np.flatnonzero((data >= 0).any(axis=1)), np.flatnonzero((data >= 0).any(axis=0))
    r0, c0 = max(0, rows[0] - margin), max(0, cols[0] - margin)
    r1, c1 = rows[-1] + 1 + margin, cols[-1] + 1 + margin
    origin = (round(raster.origin[0] + c0 * resolution, 9), round(raster.origin[1] + r0 * resolution, 9), 0.0)
    return OccupancyMap(np.ascontiguousarray(data[r0:r1, c0:c1]), float(resolution), origin)
