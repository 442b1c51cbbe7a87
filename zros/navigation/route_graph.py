"""nav2_route's route graph as plain data: loading Nav2's GeoJSON graph files, scoring edges,
searching a route, densifying it into a path and following the robot along it.

A route graph is a hand-drawn road map (lanes of a warehouse, corridors of a building): nodes
where the robot may stop or turn, directed edges it may drive. Nav2 Jazzy's route_server plans
over it instead of over the costmap; the node (`nodes/nav2_route/route_server.py`) wraps this
module, which imports no runtime so that tests and benchmarks run it directly.

The file format is Nav2's (`nav2_route/graphs/*.geojson`): a GeoJSON FeatureCollection whose
`Point` features are nodes (`properties.id`, optional `frame`, `metadata`) and whose
`MultiLineString` or `LineString` features are edges (`properties.id`, `startid`, `endid`,
optional `cost`, `overridable`, `metadata`). An edge is one-way; a two-way road is two edges.
"""
from __future__ import annotations

import json
import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

__all__ = ['RouteGraph', 'Route', 'RouteError', 'NoValidGraph', 'NoValidRoute', 'IndeterminantNodes',
           'load_graph', 'parse_graph', 'distance_costs', 'edge_costs', 'find_route', 'nearest_nodes',
           'prune_ends', 'densify', 'RouteProgress']


class RouteError(Exception):
    """A request route_server cannot serve; `code` names the ComputeRoute error code."""
    code = 'UNKNOWN'


class NoValidGraph(RouteError):
    """The graph file is missing, unreadable or inconsistent (Nav2's NO_VALID_GRAPH)."""
    code = 'NO_VALID_GRAPH'


class NoValidRoute(RouteError):
    """No chain of edges leads from the start node to the goal node (NO_VALID_ROUTE)."""
    code = 'NO_VALID_ROUTE'


class IndeterminantNodes(RouteError):
    """A start or goal pose or id matches no graph node (INDETERMINANT_NODES_ON_GRAPH)."""
    code = 'INDETERMINANT_NODES_ON_GRAPH'


@dataclass(frozen=True)
class RouteGraph:
    """Nodes and directed edges as arrays; edges refer to nodes by index, not by file id.

    `edge_cost` is the file's `cost` (0 when absent); `edge_overridable` False means that cost is
    used as is, whatever the edge scorers say (Nav2's semantics).
    """
    node_ids: np.ndarray            # (N,) int: the ids of the file
    xy: np.ndarray                  # (N, 2) float
    node_frames: tuple[str, ...]    # '' = the route frame
    edge_ids: np.ndarray            # (E,) int
    edge_start: np.ndarray          # (E,) int: node index
    edge_end: np.ndarray            # (E,) int: node index
    edge_cost: np.ndarray           # (E,) float
    edge_overridable: np.ndarray    # (E,) bool
    edge_metadata: tuple[dict, ...] = field(default=())
    node_metadata: tuple[dict, ...] = field(default=())

    def index_of(self, node_id: int) -> int:
        """The index of the node with file id `node_id`; IndeterminantNodes if there is none."""
        hits = np.flatnonzero(self.node_ids == int(node_id))
        if hits.size == 0:
            raise IndeterminantNodes(f'No node with id {node_id} in the route graph')
        return int(hits[0])

    def edge_lengths(self) -> np.ndarray:
        return np.hypot(*(self.xy[self.edge_end] - self.xy[self.edge_start]).T)


@dataclass(frozen=True)
class Route:
    """A route: node indices in travel order, the edge indices joining them (one fewer), its cost."""
    nodes: tuple[int, ...]
    edges: tuple[int, ...]
    cost: float


def load_graph(path: str | Path) -> RouteGraph:
    """Read a Nav2 GeoJSON graph file; NoValidGraph with a one-line reason if it cannot be used."""
    try:
        text = Path(path).read_text()
    except OSError as exc:
        raise NoValidGraph(f'Cannot read the graph file {path}: {exc.strerror or exc}') from None
    try:
        data = json.loads(text)
    except json.JSONDecodeError as exc:
        raise NoValidGraph(f'{path} is not JSON: {exc.msg} at line {exc.lineno}') from None
    try:
        return parse_graph(data)
    except NoValidGraph as exc:
        raise NoValidGraph(f'{path}: {exc}') from None


def parse_graph(data: dict) -> RouteGraph:
    """A RouteGraph from a decoded GeoJSON FeatureCollection (see the module docstring)."""
    features = data.get('features') if isinstance(data, dict) else None
    if not isinstance(features, list):
        raise NoValidGraph('not a GeoJSON FeatureCollection (no "features" list)')
    nodes, edges = [], []
    for feature in features:
        kind = (feature.get('geometry') or {}).get('type')
        if kind == 'Point':
            nodes.append(feature)
        elif kind in ('MultiLineString', 'LineString'):
            edges.append(feature)
    if not nodes or not edges:
        raise NoValidGraph('the graph has no nodes or no edges')
    try:
        node_ids = np.array([int(f['properties']['id']) for f in nodes], np.int64)
        xy = np.array([[float(c) for c in f['geometry']['coordinates'][:2]] for f in nodes], np.float64)
    except (KeyError, TypeError, ValueError, IndexError):
        raise NoValidGraph('a node lacks an integer "id" or x, y coordinates') from None
    index = {int(i): k for k, i in enumerate(node_ids.tolist())}
    rows = []
    for f in edges:
        props = f.get('properties') or {}
        try:
            eid, start, end = int(props['id']), int(props['startid']), int(props['endid'])
        except (KeyError, TypeError, ValueError):
            raise NoValidGraph('an edge lacks an integer "id", "startid" or "endid"') from None
        for end_name, nid in (('Start', start), ('End', end)):
            if nid not in index:
                raise NoValidGraph(f'{end_name} id {nid} does not exist for edge id {eid}')
        rows.append((eid, index[start], index[end], float(props.get('cost', 0.0)),
                     bool(props.get('overridable', True)), dict(props.get('metadata') or {})))
    return RouteGraph(
        node_ids=node_ids, xy=xy,
        node_frames=tuple(str((f.get('properties') or {}).get('frame', '')) for f in nodes),
        edge_ids=np.array([r[0] for r in rows], np.int64),
        edge_start=np.array([r[1] for r in rows], np.int64),
        edge_end=np.array([r[2] for r in rows], np.int64),
        edge_cost=np.array([r[3] for r in rows], np.float64),
        edge_overridable=np.array([r[4] for r in rows], bool),
        edge_metadata=tuple(r[5] for r in rows),
        node_metadata=tuple(dict((f.get('properties') or {}).get('metadata') or {}) for f in nodes))


def distance_costs(graph: RouteGraph, *, weight: float = 1.0, speed_tag: str = 'speed_limit') -> np.ndarray:
    """nav2_route::DistanceScorer: weight x edge length / the edge's `speed_tag` metadata (1 if unset)."""
    speed = np.array([float(m.get(speed_tag, 1.0)) for m in graph.edge_metadata] or np.ones(0))
    speed = np.where(speed > 0.0, speed, 1.0) if speed.size else np.ones(len(graph.edge_ids))
    return weight * graph.edge_lengths() / speed


def edge_costs(graph: RouteGraph, scored: np.ndarray | None) -> np.ndarray:
    """The cost the search uses per edge: the scorers' sum (`scored`, None when there are no
    scorers) where the edge is overridable, else the file's cost, which must then be positive."""
    fixed = ~graph.edge_overridable if scored is not None else np.ones(len(graph.edge_ids), bool)
    bad = fixed & (graph.edge_cost <= 0.0)
    if bad.any():
        raise NoValidGraph(f'Edge {int(graph.edge_ids[np.argmax(bad)])} has no cost in the file and '
                           'no edge scorer may set one')
    return np.where(fixed, graph.edge_cost, scored if scored is not None else 0.0)


def find_route(graph: RouteGraph, start: int, goal: int, costs: np.ndarray,
               blocked_edge_ids: tuple[int, ...] = ()) -> Route:
    """The cheapest route from node index `start` to `goal` over the directed edges (Dijkstra,
    scipy's). Where two edges join the same pair of nodes the cheaper is taken. NoValidRoute if
    the goal cannot be reached."""
    from scipy.sparse import csr_matrix
    from scipy.sparse.csgraph import dijkstra
    if start == goal:
        return Route((start,), (), 0.0)
    usable = ~np.isin(graph.edge_ids, np.asarray(blocked_edge_ids, np.int64)) & np.isfinite(costs)
    order = np.flatnonzero(usable)
    order = order[np.lexsort((costs[order], graph.edge_end[order], graph.edge_start[order]))]
    pair = graph.edge_start[order] * len(graph.node_ids) + graph.edge_end[order]
    keep = order[np.r_[True, pair[1:] != pair[:-1]]] if order.size else order
    n = len(graph.node_ids)
    # csgraph drops explicit zeros (no edge): a zero-length edge costs a hair instead.
    weights = np.maximum(costs[keep], 1e-9)
    matrix = csr_matrix((weights, (graph.edge_start[keep], graph.edge_end[keep])), shape=(n, n))
    dist, pred = dijkstra(matrix, directed=True, indices=start, return_predecessors=True)
    if not np.isfinite(dist[goal]):
        raise NoValidRoute(f'Could not find a route from node {int(graph.node_ids[start])} '
                           f'to node {int(graph.node_ids[goal])}')
    nodes = [goal]
    while nodes[-1] != start:
        nodes.append(int(pred[nodes[-1]]))
    nodes.reverse()
    edge_of = {(int(graph.edge_start[e]), int(graph.edge_end[e])): int(e) for e in keep}
    edges = tuple(edge_of[(a, b)] for a, b in zip(nodes[:-1], nodes[1:]))
    return Route(tuple(nodes), edges, float(sum(costs[e] for e in edges)))


def nearest_nodes(graph: RouteGraph, xy: tuple[float, float], count: int = 1) -> np.ndarray:
    """Indices of the `count` nodes nearest to `xy`, nearest first (Euclidean)."""
    d = np.hypot(*(graph.xy - np.asarray(xy, np.float64)).T)
    return np.argsort(d, kind='stable')[:max(1, count)]


def _projects_onto(a: np.ndarray, b: np.ndarray, p: np.ndarray) -> tuple[float, float]:
    """(cosine between a->b and a->p, distance from p to segment a-b)."""
    ab, ap = b - a, p - a
    denom = float(np.hypot(*ab) * np.hypot(*ap))
    cos = float(ab @ ap) / denom if denom > 0 else 0.0
    t = float(np.clip((ap @ ab) / max(float(ab @ ab), 1e-12), 0.0, 1.0))
    return cos, float(np.hypot(*(a + t * ab - p)))


def prune_ends(graph: RouteGraph, route: Route, costs: np.ndarray, start_xy: tuple[float, float] | None,
               goal_xy: tuple[float, float] | None, *, max_dist_from_edge: float = 8.0,
               min_dist_from_start: float = 0.10, min_dist_from_goal: float = 0.15) -> Route:
    """Drop the first edge when the start pose already lies along it past its first node, and the
    last edge when the goal lies before its last node (Nav2's goal intent pruning: a robot midway
    along the first edge does not drive back to its start node). None skips that end."""
    nodes, edges, cost = list(route.nodes), list(route.edges), route.cost
    if start_xy is not None and edges:
        a, b, p = graph.xy[nodes[0]], graph.xy[nodes[1]], np.asarray(start_xy, np.float64)
        cos, off = _projects_onto(a, b, p)
        if cos > 1e-6 and float(np.hypot(*(p - a))) > min_dist_from_start and off <= max_dist_from_edge:
            cost -= float(costs[edges[0]])
            nodes, edges = nodes[1:], edges[1:]
    if goal_xy is not None and edges:
        a, b, p = graph.xy[nodes[-2]], graph.xy[nodes[-1]], np.asarray(goal_xy, np.float64)
        cos, off = _projects_onto(b, a, p)
        if cos > 1e-6 and float(np.hypot(*(p - b))) > min_dist_from_goal and off <= max_dist_from_edge:
            cost -= float(costs[edges[-1]])
            nodes, edges = nodes[:-1], edges[:-1]
    return Route(tuple(nodes), tuple(edges), max(0.0, cost))


def densify(graph: RouteGraph, route: Route, density: float = 0.05) -> tuple[np.ndarray, np.ndarray]:
    """(M, 2) points every <= `density` m along the route's edges, ending on its last node, and
    each point's heading (towards the next point; the last edge's direction at the end)."""
    corners = graph.xy[list(route.nodes)]
    if len(corners) == 1:
        return corners.copy(), np.zeros(1)
    pieces = []
    for a, b in zip(corners[:-1], corners[1:]):
        n = int(math.ceil(float(np.hypot(*(b - a))) / density))
        if n >= 1:
            pieces.append(a + (b - a) * (np.arange(n)[:, None] / n))
    points = np.vstack(pieces + [corners[-1:]])
    d = np.diff(points, axis=0)
    last = corners[-1] - corners[-2]
    yaws = np.append(np.arctan2(d[:, 1], d[:, 0]), math.atan2(last[1], last[0]))
    return points, yaws


class RouteProgress:
    """Where the robot is along a route, updated from its position (Nav2's route tracker).

    A node counts as passed once the robot is within `radius` of it (`boundary_radius` for the
    route's first and last node) and then either leaves that circle or crosses the bisector of
    the turn at the node. `update` returns True when a node was passed; `done` once the last one
    was.
    """

    def __init__(self, graph: RouteGraph, route: Route, *, radius: float = 2.0,
                 boundary_radius: float = 1.0) -> None:
        self.graph, self.route = graph, route
        self.radius, self.boundary_radius = radius, boundary_radius
        self.edge_index = -1                      # index into route.edges of the edge being driven
        self.last_node: int | None = None
        self.next_node: int | None = route.nodes[0]
        self._within = False

    @property
    def done(self) -> bool:
        return self.next_node is None

    @property
    def current_edge(self) -> int | None:
        return self.route.edges[self.edge_index] if 0 <= self.edge_index < len(self.route.edges) else None

    def _is_boundary(self) -> bool:
        return self.edge_index == len(self.route.edges) - 1 or self.edge_index == -1

    def _achieved(self, xy: np.ndarray) -> bool:
        target = self.graph.xy[self.next_node]
        dx, dy = target - xy
        dist = math.hypot(dx, dy)
        boundary = self._is_boundary()
        inside = dist <= (self.boundary_radius if boundary else self.radius)
        if dist < 1e-4 or (not inside and self._within):
            return True
        self._within = inside
        if boundary or not inside:
            return inside
        n = target - self.graph.xy[self.route.nodes[self.edge_index]]
        m = self.graph.xy[self.route.nodes[self.edge_index + 2]] - target
        nm, mm = float(np.hypot(*n)), float(np.hypot(*m))
        if nm < 1e-6 or mm < 1e-6:
            return True
        bisector = n * mm + m * nm
        return float(bisector @ np.array([dx, dy])) <= 0.0

    def update(self, xy: tuple[float, float]) -> bool:
        """Advance with the robot's position; True if it passed a node."""
        if self.done or not self._achieved(np.asarray(xy, np.float64)):
            return False
        self._within = False
        self.last_node = self.next_node
        self.edge_index += 1
        self.next_node = (self.route.nodes[self.edge_index + 1]
                          if self.edge_index < len(self.route.edges) else None)
        return True
