"""Global planner on a costmap: Dijkstra over the 8-connected grid (NavFn's role) and path smoothing.

Cell traversal costs follow NavFn: a free cell costs COST_NEUTRAL (50), a cell of cost c costs
50 + 0.8 c, unknown cells cost 253 when `allow_unknown` (else they are walls), lethal cells are
walls. Cells inside the inscribed radius are walls for the goal but not for getting out of them:
they cost a large constant, so a robot that starts touching a wall still gets a path out.

The graph is built once per costmap (vectorised, scipy.sparse) and searched with
scipy.sparse.csgraph's Dijkstra; a goal the search does not reach, or one in an inflated cell, is
moved to the best reachable cell within `tolerance` [m], as NavFn does. Failures carry Nav2's
ComputePathToPose error codes.

Reference: navigation2 nav2_navfn_planner (navfn.cpp, navfn_planner.cpp) and nav2_smoother's
SimpleSmoother for the smoothing weights.
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import dijkstra

from zros.navigation.costmap import INSCRIBED_INFLATED_OBSTACLE, LETHAL_OBSTACLE, NO_INFORMATION, LayeredCostmap
from zros.navigation.path_smoother import taut_step

__all__ = ['PlanningError', 'GridPlanner', 'smooth_path', 'path_yaws',
           'UNKNOWN', 'START_OUTSIDE_MAP', 'GOAL_OUTSIDE_MAP', 'START_OCCUPIED', 'GOAL_OCCUPIED',
           'NO_VALID_PATH']

# nav2_msgs/action/ComputePathToPose result codes.
UNKNOWN = 200
START_OUTSIDE_MAP = 203
GOAL_OUTSIDE_MAP = 204
START_OCCUPIED = 205
GOAL_OCCUPIED = 206
NO_VALID_PATH = 208

COST_NEUTRAL = 50.0
COST_FACTOR = 0.8
_UNKNOWN_COST = 253.0
_INSCRIBED_COST = 5000.0    # escape-only: far dearer than any detour through free space

# (d_row, d_col) of a cell's eight neighbours.
_NEIGHBOURS = ((0, 1), (1, 0), (0, -1), (-1, 0), (1, 1), (1, -1), (-1, 1), (-1, -1))


@lru_cache(maxsize=4)
def _grid_edges(rows: int, cols: int) -> tuple[np.ndarray, np.ndarray]:
    """The 8-connected grid's edges in CSR order: (rows*cols, 8) neighbour indices (a cell's own
    index where the neighbour is off the grid) and (8,) lengths [cells]. Built once per map size,
    so that a costmap update only recomputes the weights."""
    r, c = np.divmod(np.arange(rows * cols), cols)
    neighbours = np.empty((rows * cols, 8), np.int32)
    for k, (dr, dc) in enumerate(_NEIGHBOURS):
        nr, nc = r + dr, c + dc
        inside = (nr >= 0) & (nr < rows) & (nc >= 0) & (nc < cols)
        neighbours[:, k] = np.where(inside, nr * cols + nc, r * cols + c)
    lengths = np.hypot(*np.array(_NEIGHBOURS, np.float64).T)
    return neighbours, lengths


class PlanningError(Exception):
    """A request the planner cannot serve; `code` is the ComputePathToPose error code."""

    def __init__(self, code: int, message: str) -> None:
        super().__init__(message)
        self.code = code


@dataclass
class _Graph:
    matrix: object
    cell_cost: np.ndarray


class GridPlanner:
    """Plans on one LayeredCostmap; call `invalidate()` after the costmap's master grid changes."""

    def __init__(self, costmap: LayeredCostmap, *, tolerance: float = 0.5, allow_unknown: bool = True,
                 smooth: bool = True) -> None:
        self.costmap = costmap
        self.tolerance = tolerance
        self.allow_unknown = allow_unknown
        self.smooth = smooth
        self._graph: _Graph | None = None

    def invalidate(self) -> None:
        self._graph = None

    def _build(self) -> _Graph:
        costs = self.costmap.master
        cell = COST_NEUTRAL + COST_FACTOR * costs.astype(np.float64)
        cell[costs == INSCRIBED_INFLATED_OBSTACLE] = _INSCRIBED_COST
        cell[costs == LETHAL_OBSTACLE] = np.inf
        cell[costs == NO_INFORMATION] = _UNKNOWN_COST if self.allow_unknown else np.inf
        neighbours, lengths = _grid_edges(*costs.shape)
        flat = cell.ravel()
        # An edge costs its length times the mean of its two cells; an edge into or out of a wall
        # (or off the grid: a self-loop there) is infinite, which Dijkstra never takes.
        weight = lengths * 0.5 * (flat[:, None] + flat[neighbours])
        n = flat.size
        matrix = csr_matrix((weight.ravel(), neighbours.ravel(), np.arange(0, 8 * n + 1, 8)), shape=(n, n))
        return _Graph(matrix, cell)

    def plan(self, start: tuple[float, float], goal: tuple[float, float]) -> np.ndarray:
        """Return the path as (N, 2) points [m] from `start` to `goal` (or the cell the goal was
        moved to), smoothed; raise PlanningError otherwise."""
        cm = self.costmap
        geometry = cm.geometry
        s = tuple(int(i) for i in geometry.world_to_cell(start[0], start[1]))
        g = tuple(int(i) for i in geometry.world_to_cell(goal[0], goal[1]))
        if not geometry.contains(*s):
            raise PlanningError(START_OUTSIDE_MAP, f'Start Coordinates of ({start[0]:.2f}, {start[1]:.2f}) was outside bounds')
        if not geometry.contains(*g):
            raise PlanningError(GOAL_OUTSIDE_MAP, f'Goal Coordinates of ({goal[0]:.2f}, {goal[1]:.2f}) was outside bounds')
        master = cm.master
        if master[s] == LETHAL_OBSTACLE:
            raise PlanningError(START_OCCUPIED, f'Start Coordinates of ({start[0]:.2f}, {start[1]:.2f}) was in lethal cost')
        if master[g] == LETHAL_OBSTACLE:
            raise PlanningError(GOAL_OCCUPIED, f'Goal Coordinates of ({goal[0]:.2f}, {goal[1]:.2f}) was in lethal cost')
        if self._graph is None:
            self._graph = self._build()
        start_index, goal_index = int(geometry.index(*s)), int(geometry.index(*g))
        # Search a cost radius that covers a path a few times longer than the straight line through
        # moderately inflated cells first (a fraction of the map); the whole map only if that misses.
        reach = (np.hypot(s[0] - g[0], s[1] - g[1]) + self.tolerance / cm.resolution) * 3.0 * 2 * COST_NEUTRAL + 1000.0
        for limit in (reach, np.inf):
            dist, pred = dijkstra(self._graph.matrix, indices=start_index, return_predecessors=True,
                                  limit=limit)
            target = self._reachable_goal(g, dist)
            if target is not None:
                break
        if target is None:
            raise PlanningError(NO_VALID_PATH, f'Failed to create plan with tolerance of: {self.tolerance:.2f}')
        cells = [target]
        while cells[-1] != start_index:
            cells.append(int(pred[cells[-1]]))
        cells.reverse()
        points = np.column_stack(geometry.cell_centre(*geometry.cell_of_index(np.asarray(cells))))
        points[0] = start
        if target == goal_index:
            points[-1] = goal
        if self.smooth and len(points) > 2:
            points = smooth_path(points, cm)
        return points

    def _reachable_goal(self, g: tuple[int, int], dist: np.ndarray) -> int | None:
        master = self.costmap.master
        rows, cols = master.shape
        index = g[0] * cols + g[1]
        if np.isfinite(dist[index]) and master[g] < INSCRIBED_INFLATED_OBSTACLE:
            return index
        reach = int(np.ceil(self.tolerance / self.costmap.resolution))
        r0, r1 = max(0, g[0] - reach), min(rows, g[0] + reach + 1)
        c0, c1 = max(0, g[1] - reach), min(cols, g[1] + reach + 1)
        rr, cc = np.mgrid[r0:r1, c0:c1]
        rr, cc = rr.ravel(), cc.ravel()
        d_goal = np.hypot(rr - g[0], cc - g[1]) * self.costmap.resolution
        flat = rr * cols + cc
        ok = (d_goal <= self.tolerance) & np.isfinite(dist[flat]) & (master[rr, cc] < INSCRIBED_INFLATED_OBSTACLE)
        if not ok.any():
            return None
        best = np.lexsort((dist[flat][ok], d_goal[ok]))[0]
        return int(flat[ok][best])


def smooth_path(points: np.ndarray, costmap: LayeredCostmap, *, w_data: float = 0.2, w_smooth: float = 0.3,
                iterations: int = 200) -> np.ndarray:
    """Pull the path taut (Nav2 SimpleSmoother's update, all points at once per iteration); a point
    that would move into an inscribed or lethal cell keeps its previous position, and the rest go
    on (unlike the smoother_server's SimpleSmoother, which stops: the planner's paths may start
    touching a wall and must still be smoothed). The ends stay."""
    original = np.asarray(points, np.float64)
    path = original.copy()
    for _ in range(iterations):
        inner = path[1:-1]
        update = taut_step(path, original, w_data, w_smooth)
        bad = costmap.cost_at(update) >= INSCRIBED_INFLATED_OBSTACLE
        bad &= costmap.cost_at(inner) < INSCRIBED_INFLATED_OBSTACLE
        update[bad] = inner[bad]
        if np.abs(update - inner).max(initial=0.0) < 1e-5:
            path[1:-1] = update
            break
        path[1:-1] = update
    return path


def path_yaws(points: np.ndarray, final_yaw: float) -> np.ndarray:
    """Heading of each path point [rad]: towards the next point; the last takes `final_yaw`."""
    d = np.diff(points, axis=0)
    yaws = np.empty(len(points))
    yaws[:-1] = np.arctan2(d[:, 1], d[:, 0])
    yaws[-1] = final_yaw
    return yaws
