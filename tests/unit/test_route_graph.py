"""nav2_route's graph as plain code: Nav2's GeoJSON read, distance scoring, the cheapest route over
one-way edges, pruning the ends a robot has already passed, densifying, and following a robot."""
from __future__ import annotations

import json

import numpy as np
import pytest

from zros.navigation.route_graph import (IndeterminantNodes, NoValidGraph, NoValidRoute, RouteProgress,
                                         densify, distance_costs, edge_costs, find_route, load_graph,
                                         nearest_nodes, parse_graph, prune_ends)


def _feature_collection(nodes: dict[int, tuple[float, float]], edges: list[tuple[int, int, int, dict]]) -> dict:
    features = [{'type': 'Feature', 'properties': {'id': i},
                 'geometry': {'type': 'Point', 'coordinates': list(xy)}} for i, xy in nodes.items()]
    for eid, a, b, extra in edges:
        features.append({'type': 'Feature', 'properties': {'id': eid, 'startid': a, 'endid': b, **extra},
                         'geometry': {'type': 'MultiLineString', 'coordinates': [[list(nodes[a]), list(nodes[b])]]}})
    return {'type': 'FeatureCollection', 'features': features}


# A square 0-1-2-3 (2 m sides) whose edges run both ways, plus a one-way diagonal 0 -> 2.
SQUARE = {1: (0.0, 0.0), 2: (2.0, 0.0), 3: (2.0, 2.0), 4: (0.0, 2.0)}
RING = [(10, 1, 2, {}), (11, 2, 3, {}), (12, 3, 4, {}), (13, 4, 1, {}),
        (20, 2, 1, {}), (21, 3, 2, {}), (22, 4, 3, {}), (23, 1, 4, {})]


def _square(*extra_edges) -> object:
    return parse_graph(_feature_collection(SQUARE, RING + list(extra_edges)))


def test_reads_nav2s_geojson_file(tmp_path):
    path = tmp_path / 'graph.geojson'
    path.write_text(json.dumps(_feature_collection(SQUARE, RING + [(30, 1, 3, {'cost': 9.5, 'overridable': False,
                                                                                 'metadata': {'speed_limit': 0.5}})])))
    graph = load_graph(path)
    assert graph.node_ids.tolist() == [1, 2, 3, 4]
    assert graph.xy[graph.index_of(3)].tolist() == [2.0, 2.0]
    assert len(graph.edge_ids) == 9
    diagonal = int(np.flatnonzero(graph.edge_ids == 30)[0])
    assert graph.edge_cost[diagonal] == 9.5 and not graph.edge_overridable[diagonal]
    assert graph.edge_metadata[diagonal] == {'speed_limit': 0.5}


@pytest.mark.parametrize('content, fragment', [
    ('not json', 'is not JSON'),
    ('{"type": "FeatureCollection"}', 'no "features" list'),
    (json.dumps(_feature_collection({1: (0, 0)}, [])), 'no nodes or no edges'),
    (json.dumps(_feature_collection({1: (0, 0), 2: (1, 0)}, [(5, 1, 2, {})]))
     .replace('"endid": 2', '"endid": 7'), 'End id 7 does not exist for edge id 5'),
])
def test_a_bad_graph_file_is_one_line(tmp_path, content, fragment):
    path = tmp_path / 'bad.geojson'
    path.write_text(content)
    with pytest.raises(NoValidGraph) as err:
        load_graph(path)
    assert fragment in str(err.value) and '\n' not in str(err.value)
    with pytest.raises(NoValidGraph, match='Cannot read'):
        load_graph(tmp_path / 'missing.geojson')


def test_cheapest_route_follows_one_way_edges_and_speed_limits():
    graph = _square()
    costs = edge_costs(graph, distance_costs(graph))
    route = find_route(graph, graph.index_of(1), graph.index_of(3), costs)
    assert len(route.nodes) == 3 and route.cost == pytest.approx(4.0)
    # A one-way diagonal 1 -> 3 is shorter one way only.
    graph = _square((30, 1, 3, {}))
    costs = edge_costs(graph, distance_costs(graph))
    there = find_route(graph, graph.index_of(1), graph.index_of(3), costs)
    assert graph.node_ids[list(there.nodes)].tolist() == [1, 3]
    assert graph.edge_ids[list(there.edges)].tolist() == [30]
    assert there.cost == pytest.approx(2 * np.sqrt(2))
    back = find_route(graph, graph.index_of(3), graph.index_of(1), costs)
    assert len(back.nodes) == 3
    # Slow on the diagonal (speed_limit 0.25): going round is cheaper.
    graph = _square((30, 1, 3, {'metadata': {'speed_limit': 0.25}}))
    costs = edge_costs(graph, distance_costs(graph))
    assert len(find_route(graph, graph.index_of(1), graph.index_of(3), costs).nodes) == 3
    # A blocked edge is routed around.
    graph = _square((30, 1, 3, {}))
    costs = edge_costs(graph, distance_costs(graph))
    assert 30 not in graph.edge_ids[list(find_route(graph, 0, 2, costs, blocked_edge_ids=(30,)).edges)]


def test_fixed_costs_and_unreachable_goals():
    graph = _square((30, 1, 3, {'cost': 100.0, 'overridable': False}))
    costs = edge_costs(graph, distance_costs(graph))
    assert 30 not in graph.edge_ids[list(find_route(graph, 0, 2, costs).edges)]
    with pytest.raises(NoValidGraph, match='Edge 10 has no cost'):
        edge_costs(graph, None)          # no scorers: every edge needs the file's cost
    one_way = parse_graph(_feature_collection({1: (0, 0), 2: (1, 0), 3: (5, 5)}, [(1, 1, 2, {}), (2, 3, 2, {})]))
    with pytest.raises(NoValidRoute, match='from node 1 to node 3'):
        find_route(one_way, 0, 2, distance_costs(one_way))
    assert find_route(one_way, 1, 1, distance_costs(one_way)).nodes == (1,)
    with pytest.raises(IndeterminantNodes):
        one_way.index_of(42)


def test_nearest_nodes_prune_and_densify():
    graph = _square()
    costs = distance_costs(graph)
    assert nearest_nodes(graph, (1.9, -0.3), 2).tolist() == [1, 0]
    route = find_route(graph, 0, 2, costs)                     # 1 -> 2 -> 3 or 1 -> 4 -> 3
    first, second = graph.xy[route.nodes[0]], graph.xy[route.nodes[1]]
    midway = tuple(0.5 * (first + second))
    pruned = prune_ends(graph, route, costs, midway, None)
    assert pruned.nodes == route.nodes[1:] and pruned.cost == pytest.approx(2.0)
    behind = tuple(first - 0.5 * (second - first))             # behind the start node: keep the edge
    assert prune_ends(graph, route, costs, behind, None) == route
    last, before = graph.xy[route.nodes[-1]], graph.xy[route.nodes[-2]]
    short_of_goal = tuple(before + 0.5 * (last - before))
    assert prune_ends(graph, route, costs, None, short_of_goal).nodes == route.nodes[:-1]
    points, yaws = densify(graph, route, 0.05)
    assert len(points) == 81                                    # 4 m every 5 cm, plus the end node
    assert points[0] == pytest.approx(first) and points[-1] == pytest.approx(last)
    assert np.hypot(*np.diff(points, axis=0).T).max() <= 0.05 + 1e-9
    assert yaws[-1] == pytest.approx(np.arctan2(*(last - before)[::-1]))
    single, heading = densify(graph, find_route(graph, 3, 3, costs))
    assert single.tolist() == [graph.xy[3].tolist()] and heading.tolist() == [0.0]


def test_progress_passes_nodes_as_the_robot_drives():
    # A straight line of nodes 2 m apart, then a right-angle turn.
    nodes = {1: (0.0, 0.0), 2: (2.0, 0.0), 3: (4.0, 0.0), 4: (4.0, 2.0)}
    graph = parse_graph(_feature_collection(nodes, [(1, 1, 2, {}), (2, 2, 3, {}), (3, 3, 4, {})]))
    route = find_route(graph, 0, 3, distance_costs(graph))
    progress = RouteProgress(graph, route, radius=0.5, boundary_radius=0.3)
    passed = []
    for x in np.arange(0.0, 4.0, 0.05):
        if progress.update((x, 0.0)):
            passed.append((round(float(x), 2), int(graph.node_ids[progress.last_node])))
    for y in np.arange(0.0, 2.05, 0.05):
        if progress.update((4.0, y)):
            passed.append((round(float(y), 2), int(graph.node_ids[progress.last_node])))
    # Start at once; node 2 on leaving its 0.5 m circle (a straight, the bisector is crossed at it);
    # node 3 at the turn's bisector; the goal within its boundary radius.
    assert [node for _, node in passed] == [1, 2, 3, 4]
    assert passed[0][0] == 0.0 and 2.0 <= passed[1][0] <= 2.5
    assert passed[3][0] >= 1.7
    assert progress.done and progress.current_edge is None


def test_the_shipped_turtlebot3_graph_lies_in_free_space():
    """nav2_route/graphs/turtlebot3_graph.geojson (zros's own): a lattice around the nine pillars
    of zros's turtlebot3_world, every node and edge at least 0.2 m from an obstacle."""
    from pathlib import Path

    from scipy import ndimage

    from zros.sim import load_world, rasterize
    graph = load_graph(Path(__file__).resolve().parents[2] / 'nodes/nav2_route/graphs/turtlebot3_graph.geojson')
    assert len(graph.node_ids) == 16 and len(graph.edge_ids) == 48
    raster = rasterize(load_world('turtlebot3_world'), 0.05)
    clearance = ndimage.distance_transform_edt(~raster.cells.astype(bool)) * 0.05
    t = np.linspace(0.0, 1.0, 40)[:, None]
    a, b = graph.xy[graph.edge_start], graph.xy[graph.edge_end]
    points = (a[:, None, :] + t * (b - a)[:, None, :]).reshape(-1, 2)
    cols = ((points[:, 0] - raster.origin[0]) / 0.05).astype(int)
    rows = ((points[:, 1] - raster.origin[1]) / 0.05).astype(int)
    assert clearance[rows, cols].min() >= 0.2
    route = find_route(graph, int(nearest_nodes(graph, (-2.0, -0.5))[0]), int(nearest_nodes(graph, (1.7, 1.7))[0]),
                       distance_costs(graph))
    assert route.cost == pytest.approx(3 * 1.1 + 2 * 1.1)
