"""Layered 2D costmap: static, obstacle (ray-cast clearing) and inflation layers, as nav2_costmap_2d.

A costmap is a uint8 grid (row 0 = lowest y, as an OccupancyGrid) in one frame. Each update
rebuilds the master grid from its layers in Nav2's order and with Nav2's combination rules:

* static layer: `/map` translated cell by cell (unknown -> NO_INFORMATION when
  `track_unknown_space`, occupancy >= `lethal_cost_threshold` -> LETHAL, the rest FREE when
  `trinary_costmap`, else scaled);
* obstacle layer: its own grid, marked LETHAL at scan hits within `obstacle_max_range` and
  cleared to FREE along every beam up to `raytrace_max_range`; merged with "maximum, unknown
  never overrides";
* inflation layer: cost from the distance d to the nearest lethal cell: 254 at d = 0, 253 up to
  the inscribed radius, 252 * exp(-cost_scaling_factor * (d - inscribed_radius)) up to
  `inflation_radius`.

Everything is vectorised; the distance transform is scipy's exact Euclidean one.
Reference: navigation2 nav2_costmap_2d (cost_values.hpp, static_layer.cpp, obstacle_layer.cpp,
inflation_layer.cpp).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import ndimage

from zros.grid_geometry import GridGeometry, GridGeometryMixin

__all__ = [
    'FREE_SPACE', 'MAX_NON_OBSTACLE', 'INSCRIBED_INFLATED_OBSTACLE', 'LETHAL_OBSTACLE',
    'NO_INFORMATION', 'CostmapParams', 'LayeredCostmap', 'static_costs', 'inflate',
    'to_occupancy', 'footprint_from_radius', 'FOOTPRINT_SIDES',
]

FREE_SPACE = 0
MAX_NON_OBSTACLE = 252
INSCRIBED_INFLATED_OBSTACLE = 253
LETHAL_OBSTACLE = 254
NO_INFORMATION = 255

# Nav2's costmap publisher table: cost -> OccupancyGrid value (0..100, -1 unknown).
_OCCUPANCY_OF_COST = np.empty(256, np.int8)
_OCCUPANCY_OF_COST[0] = 0
_OCCUPANCY_OF_COST[1:253] = 1 + (97 * (np.arange(1, 253) - 1)) // 251
_OCCUPANCY_OF_COST[253] = 99
_OCCUPANCY_OF_COST[254] = 100
_OCCUPANCY_OF_COST[255] = -1


@dataclass
class CostmapParams:
    """Nav2 costmap parameters zros uses (names as in nav2_params.yaml)."""

    resolution: float = 0.05            # [m/cell]
    width: float = 3.0                  # [m], rolling window only
    height: float = 3.0                 # [m], rolling window only
    rolling_window: bool = False
    robot_radius: float = 0.1           # [m] inscribed radius of the round footprint
    track_unknown_space: bool = True
    lethal_cost_threshold: int = 100
    trinary_costmap: bool = True
    use_static_layer: bool = True
    use_obstacle_layer: bool = True
    use_inflation_layer: bool = True
    obstacle_max_range: float = 2.5     # [m] hits farther away are not marked
    raytrace_max_range: float = 3.0     # [m] beams clear free space up to here
    inflation_radius: float = 0.55      # [m]
    cost_scaling_factor: float = 10.0   # [1/m]
    inflate_unknown: bool = False


def static_costs(occupancy: np.ndarray, *, track_unknown_space: bool = True,
                 lethal_cost_threshold: int = 100, trinary_costmap: bool = True) -> np.ndarray:
    """Translate OccupancyGrid values (int8, -1 unknown, 0..100) into costs (uint8), as the static layer."""
    occ = np.asarray(occupancy).astype(np.int16)
    if trinary_costmap:
        costs = np.full(occ.shape, FREE_SPACE, np.uint8)
    else:
        costs = np.clip(occ, 0, 100).astype(np.float64) * LETHAL_OBSTACLE / 100.0
        costs = np.minimum(costs.astype(np.uint8), MAX_NON_OBSTACLE).astype(np.uint8)
    costs[occ >= lethal_cost_threshold] = LETHAL_OBSTACLE
    costs[occ < 0] = NO_INFORMATION if track_unknown_space else FREE_SPACE
    return costs


def inflate(costs: np.ndarray, resolution: float, *, inscribed_radius: float, inflation_radius: float,
            cost_scaling_factor: float, inflate_unknown: bool = False) -> np.ndarray:
    """Return a copy of `costs` with the inflation layer applied (Nav2's exponential decay).

    The distance is measured between cell centres, in metres. An unknown cell takes the
    inflated cost only if it is at least INSCRIBED (or any cost with `inflate_unknown`).
    """
    lethal = costs == LETHAL_OBSTACLE
    out = costs.copy()
    if not lethal.any():
        return out
    dist = ndimage.distance_transform_edt(~lethal) * resolution
    within = dist <= inflation_radius + 1e-9
    inflated = np.zeros(costs.shape, np.uint8)
    scaled = MAX_NON_OBSTACLE * np.exp(-cost_scaling_factor * (dist[within] - inscribed_radius))
    inflated[within] = np.clip(scaled, 0, MAX_NON_OBSTACLE).astype(np.uint8)
    inflated[within & (dist <= inscribed_radius)] = INSCRIBED_INFLATED_OBSTACLE
    inflated[lethal] = LETHAL_OBSTACLE
    unknown = costs == NO_INFORMATION
    take = inflated > costs
    take &= ~unknown
    if inflate_unknown:
        take |= unknown & (inflated > FREE_SPACE)
    else:
        take |= unknown & (inflated >= INSCRIBED_INFLATED_OBSTACLE)
    out[take] = inflated[take]
    return out


#: Corners of a round robot's footprint polygon (Nav2's makeFootprintFromRadius).
FOOTPRINT_SIDES = 16


def footprint_from_radius(radius: float, pose: tuple[float, float, float] = (0.0, 0.0, 0.0)) -> np.ndarray:
    """A round robot's footprint as a polygon ((FOOTPRINT_SIDES, 2) corners [m] on the circle of
    `radius`), placed at `pose` (x, y, yaw): what a costmap publishes as `published_footprint`,
    so that a collision monitor's zone can take the robot's shape from it."""
    angles = np.arange(FOOTPRINT_SIDES) * (2.0 * np.pi / FOOTPRINT_SIDES) + pose[2]
    return np.column_stack([pose[0] + radius * np.cos(angles), pose[1] + radius * np.sin(angles)])


def to_occupancy(costs: np.ndarray) -> np.ndarray:
    """Costs -> OccupancyGrid values (int8), with the table Nav2's costmap publisher uses."""
    return _OCCUPANCY_OF_COST[costs]


class LayeredCostmap(GridGeometryMixin):
    """A costmap in one frame: its layers, its master grid and the grid geometry.

    `geometry` places the cells in the costmap frame (yaw 0: Nav2's costmaps ignore a map's
    origin yaw). A rolling window keeps `width` x `height` metres centred on the robot
    (`move_to`); otherwise the grid takes the static map's size (`set_static_map`).
    """

    def __init__(self, params: CostmapParams) -> None:
        self.params = params
        size = (max(1, round(params.height / params.resolution)), max(1, round(params.width / params.resolution)))
        self.geometry = GridGeometry(params.resolution, (0.0, 0.0), size)
        self._static: np.ndarray | None = None
        self._static_geometry: GridGeometry | None = None
        self._obstacles = np.full(size, NO_INFORMATION, np.uint8)
        self.master = np.full(size, self._default_value(), np.uint8)

    # -- geometry --------------------------------------------------------------------------------
    @property
    def origin(self) -> np.ndarray:
        """(x, y) [m] of cell (0, 0)'s lower-left corner in the costmap frame (a copy)."""
        return np.array(self.geometry.origin[:2])

    def cost_at(self, xy: np.ndarray) -> np.ndarray:
        """Master cost at (N, 2) points; NO_INFORMATION outside the grid."""
        rows, cols, inside = self._cells(xy)
        out = np.full(len(cols), NO_INFORMATION, np.uint8)
        out[inside] = self.master[rows[inside], cols[inside]]
        return out

    def _cells(self, xy: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(N, 2) points [m] -> (rows, cols, inside), unbounded int cells of the master grid."""
        xy = np.atleast_2d(np.asarray(xy, np.float64))
        rows, cols = self.geometry.world_to_cell(xy[:, 0], xy[:, 1])
        return rows, cols, self.geometry.contains(rows, cols)

    def _default_value(self) -> int:
        return NO_INFORMATION if self.params.track_unknown_space else FREE_SPACE

    # -- inputs ----------------------------------------------------------------------------------
    def set_static_map(self, occupancy: np.ndarray, resolution: float, origin: tuple[float, float]) -> None:
        """Take a new map (OccupancyGrid data reshaped to (height, width)); a non-rolling costmap
        adopts its size, origin and resolution, as Nav2's global costmap does."""
        costs = static_costs(occupancy, track_unknown_space=self.params.track_unknown_space,
                             lethal_cost_threshold=self.params.lethal_cost_threshold,
                             trinary_costmap=self.params.trinary_costmap)
        geometry = GridGeometry(resolution, (origin[0], origin[1]), costs.shape)
        if self.params.rolling_window:
            self._static_geometry = geometry
            self._static = costs
            return
        self.geometry = geometry
        self._static = costs
        if self._obstacles.shape != costs.shape:
            self._obstacles = np.full(costs.shape, NO_INFORMATION, np.uint8)
        self.master = costs.copy()

    def move_to(self, x: float, y: float) -> None:
        """Centre a rolling window on (x, y), keeping the obstacle marks that stay inside."""
        rows, cols = self.shape
        new_origin = np.floor((np.array([x, y]) - np.array([cols, rows]) * self.resolution / 2)
                              / self.resolution) * self.resolution
        shift = np.round((new_origin - self.origin) / self.resolution).astype(int)
        if not shift.any():
            return
        moved = np.full(self._obstacles.shape, NO_INFORMATION, np.uint8)
        dc, dr = shift
        src_r = slice(max(dr, 0), rows + min(dr, 0))
        dst_r = slice(max(-dr, 0), rows + min(-dr, 0))
        src_c = slice(max(dc, 0), cols + min(dc, 0))
        dst_c = slice(max(-dc, 0), cols + min(-dc, 0))
        if abs(dr) < rows and abs(dc) < cols:
            moved[dst_r, dst_c] = self._obstacles[src_r, src_c]
        self._obstacles = moved
        self.geometry = GridGeometry(self.resolution, (new_origin[0], new_origin[1]), self.shape)

    def add_scan(self, sensor_xy: tuple[float, float], angles: np.ndarray, ranges: np.ndarray,
                 range_min: float, range_max: float) -> None:
        """Mark and clear the obstacle layer with one scan, already in the costmap frame
        (`angles` are the beams' world directions [rad]).

        A finite reading in range clears the cells before its hit and marks the hit (when within
        obstacle_max_range); a reading beyond range_max or +inf ("no return") clears up to
        raytrace_max_range. NaN and readings below range_min are ignored.
        """
        if not self.params.use_obstacle_layer:
            return
        ranges = np.asarray(ranges, np.float64)
        angles = np.asarray(angles, np.float64)
        ok = ~np.isnan(ranges) & (ranges >= range_min)
        hit = ok & np.isfinite(ranges) & (ranges <= range_max)
        miss = ok & ~hit & (ranges > 0)
        origin = np.asarray(sensor_xy, np.float64)
        dirs = np.stack([np.cos(angles), np.sin(angles)], axis=1)
        clear_len = np.where(hit, np.minimum(ranges, self.params.raytrace_max_range),
                             self.params.raytrace_max_range)
        clear_len[~(hit | miss)] = 0.0
        self._clear_rays(origin, dirs, clear_len, hit & (ranges <= self.params.raytrace_max_range))
        mark = hit & (ranges <= self.params.obstacle_max_range)
        points = origin + dirs[mark] * ranges[mark, None]
        rows, cols, inside = self._cells(points)
        self._obstacles[rows[inside], cols[inside]] = LETHAL_OBSTACLE

    def _clear_rays(self, origin: np.ndarray, dirs: np.ndarray, lengths: np.ndarray, ends_at_hit: np.ndarray) -> None:
        """Set FREE along each ray, sampled every half cell; a ray that ends at a hit stops one
        cell short of it so that the hit's own cell is left for marking."""
        step = self.resolution * 0.5
        reach = np.where(ends_at_hit, lengths - self.resolution, lengths)
        if reach.size == 0 or reach.max() <= 0:
            return
        t = np.arange(0.0, reach.max() + 1e-9, step)
        keep = t[None, :] <= reach[:, None]
        pts = origin + dirs[:, None, :] * t[None, :, None]
        pts = pts[keep]
        rows, cols, inside = self._cells(pts)
        self._obstacles[rows[inside], cols[inside]] = FREE_SPACE

    def clear(self) -> None:
        """Forget every obstacle mark (the clear_entirely_* services)."""
        self._obstacles[:] = NO_INFORMATION

    def clear_square(self, centre: tuple[float, float], size: float, *, outside: bool = False) -> None:
        """Forget the obstacle marks in the square of side `size` [m] centred on `centre`, or
        outside it (Nav2's clear_around_* and clear_except_* services)."""
        x, y = self.geometry.centres()
        within = (np.abs(x - centre[0]) <= size / 2) & (np.abs(y - centre[1]) <= size / 2)
        self._obstacles[within != outside] = NO_INFORMATION

    # -- the master grid -------------------------------------------------------------------------
    def update(self) -> np.ndarray:
        """Rebuild the master grid from the layers and return it."""
        p = self.params
        if p.use_static_layer and self._static is not None and not p.rolling_window:
            master = self._static.copy()
        elif p.use_static_layer and self._static is not None:
            master = self._static_window()
        else:
            master = np.full(self.shape, self._default_value(), np.uint8)
        if p.use_obstacle_layer:
            layer = self._obstacles
            known = layer != NO_INFORMATION
            take = known & ((master == NO_INFORMATION) | (layer > master))
            master[take] = layer[take]
        if p.use_inflation_layer:
            master = inflate(master, self.resolution, inscribed_radius=p.robot_radius,
                             inflation_radius=p.inflation_radius, cost_scaling_factor=p.cost_scaling_factor,
                             inflate_unknown=p.inflate_unknown)
        self.master = master
        return master

    def _static_window(self) -> np.ndarray:
        """The static map's cells under a rolling window (nearest cell; unknown outside the map)."""
        static = self._static_geometry
        rows, cols = static.world_to_cell(*self.geometry.centres())
        inside = static.contains(rows, cols)
        out = np.full(self.shape, self._default_value(), np.uint8)
        out[inside] = self._static[rows[inside], cols[inside]]
        return out
