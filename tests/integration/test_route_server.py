"""nav2_route's route_server as a process: it loads a GeoJSON graph given by Nav2 Jazzy's
parameters, answers compute_route by node ids and by poses, aborts with Nav2's error codes, takes
a new graph over its service, and tracks a robot (a TF frame the test moves) along a route."""
from __future__ import annotations

import json
import time
from typing import Any

import pytest

from conftest import activate, wait_until

# Six nodes on a 2 m grid (14 and 15 off it, so that no two routes tie), edges both ways
# between neighbours, except that 15 -> 16 is one-way; ids as a file would have them (not 0-based, not contiguous).
NODES = {11: (0.0, 0.0), 12: (2.0, 0.0), 13: (4.0, 0.0), 14: (0.0, 3.0), 15: (2.0, 2.5), 16: (4.0, 2.0)}
TWO_WAY = [(11, 12), (12, 13), (11, 14), (12, 15), (13, 16), (14, 15)]
ONE_WAY = [(15, 16)]

PARAMS = """\
route_server:
  ros__parameters:
    graph_filepath: {graph}
    boundary_radius_to_achieve_node: 0.3
    radius_to_achieve_node: 0.5
    smooth_corners: true
    path_density: 0.1
    operations: ["AdjustSpeedLimit", "ReroutingService", "CollisionMonitor"]
    ReroutingService:
      plugin: "nav2_route::ReroutingService"
    AdjustSpeedLimit:
      plugin: "nav2_route::AdjustSpeedLimit"
    CollisionMonitor:
      plugin: "nav2_route::CollisionMonitor"
      max_collision_dist: 3.0
    edge_cost_functions: ["DistanceScorer", "CostmapScorer"]
    DistanceScorer:
      plugin: "nav2_route::DistanceScorer"
    CostmapScorer:
      plugin: "nav2_route::CostmapScorer"
"""


def _graph(nodes: dict, two_way: list, one_way: list) -> str:
    features = [{'type': 'Feature', 'properties': {'id': i}, 'geometry': {'type': 'Point', 'coordinates': list(xy)}}
                for i, xy in nodes.items()]
    eid = 100
    for a, b in [*two_way, *[(b, a) for a, b in two_way], *one_way]:
        eid += 1
        features.append({'type': 'Feature', 'properties': {'id': eid, 'startid': a, 'endid': b},
                         'geometry': {'type': 'MultiLineString', 'coordinates': [[list(nodes[a]), list(nodes[b])]]}})
    return json.dumps({'type': 'FeatureCollection', 'name': 'test_graph', 'features': features})


def _pose(x: float, y: float, frame: str = 'map') -> Any:
    from interfaces.geometry_msgs.msg import PoseStamped
    p = PoseStamped()
    p.header.frame_id = frame
    p.pose.position.x, p.pose.position.y, p.pose.orientation.w = x, y, 1.0
    return p


def _run(client: Any, goal: Any, timeout: float = 20.0, feedback: list | None = None) -> tuple[int, Any]:
    """Send `goal`, wait for its result: (GoalStatus code, result)."""
    assert client.wait_for_server(timeout_sec=10)
    sent = client.send_goal_async(goal, feedback_callback=(lambda m: feedback.append(m.feedback))
                                  if feedback is not None else None)
    wait_until(sent.done, 10, message='goal response')
    handle = sent.result()
    assert handle.accepted
    got = handle.get_result_async()
    wait_until(got.done, timeout, message='goal result')
    return got.result().status, got.result().result


def test_route_server_plans_and_tracks(spawn, probe, tmp_path):
    from zros.action import ActionClient
    from interfaces.action_msgs.msg import GoalStatus
    from interfaces.nav2_msgs.action import ComputeAndTrackRoute, ComputeRoute
    from interfaces.nav2_msgs.srv import SetRouteGraph
    graph = tmp_path / 'graph.geojson'
    graph.write_text(_graph(NODES, TWO_WAY, ONE_WAY))
    params = tmp_path / 'nav2_params.yaml'
    params.write_text(PARAMS.format(graph=graph))
    server = spawn.node('nav2_route', 'route_server', '--ros-args', '--params-file', str(params))
    activate(probe, 'route_server', server)
    compute = ActionClient(probe, ComputeRoute, 'compute_route')

    # By ids: 11 -> 16 along the bottom row; 16 -> 14 may not use the one-way 15 -> 16 backwards.
    status, result = _run(compute, ComputeRoute.Goal(start_id=11, goal_id=16))
    assert status == GoalStatus.STATUS_SUCCEEDED, server.output()
    ids = [n.nodeid for n in result.route.nodes]
    assert ids == [11, 12, 13, 16]
    assert result.route.route_cost == pytest.approx(6.0)
    assert [e.edgeid for e in result.route.edges] and len(result.route.edges) == 3
    assert result.path.header.frame_id == 'map' and len(result.path.poses) == 61   # 6 m every 0.1 m, + end
    assert result.path.poses[-1].pose.position.x == pytest.approx(4.0)
    status, result = _run(compute, ComputeRoute.Goal(start_id=16, goal_id=14))
    assert [n.nodeid for n in result.route.nodes] == [16, 13, 12, 15, 14]

    # By poses: nearest nodes, and the first edge pruned when the start is already along it.
    goal = ComputeRoute.Goal(use_poses=True, use_start=True, start=_pose(1.0, 0.05), goal=_pose(4.1, 0.1))
    status, result = _run(compute, goal)
    assert status == GoalStatus.STATUS_SUCCEEDED
    assert [n.nodeid for n in result.route.nodes] == [12, 13]      # 11 -> 12 dropped: the robot is past 11

    # Failures carry nav2_route's codes.
    status, result = _run(compute, ComputeRoute.Goal(start_id=11, goal_id=99))
    assert status == GoalStatus.STATUS_ABORTED
    assert result.error_code == ComputeRoute.Result.INDETERMINANT_NODES_ON_GRAPH
    status, result = _run(compute, ComputeRoute.Goal(use_poses=True, goal=_pose(0.0, 0.0)))
    assert result.error_code == ComputeRoute.Result.TF_ERROR        # no TF for base_link yet
    assert 'Route server failed on request' in server.output()

    # A new graph over the service; a graph where the goal is unreachable.
    unreachable = tmp_path / 'unreachable.geojson'
    unreachable.write_text(_graph(NODES, [(11, 12), (12, 13)], [(13, 16)]))
    set_graph = probe.create_client(SetRouteGraph, 'route_server/set_route_graph')
    assert set_graph.wait_for_service(timeout_sec=10)
    answer = set_graph.call(SetRouteGraph.Request(graph_filepath=str(unreachable)), timeout_sec=10)
    assert answer.success
    status, result = _run(compute, ComputeRoute.Goal(start_id=16, goal_id=11))
    assert result.error_code == ComputeRoute.Result.NO_VALID_ROUTE
    bad = set_graph.call(SetRouteGraph.Request(graph_filepath=str(tmp_path / 'none.geojson')), timeout_sec=10)
    assert not bad.success

    # Tracking: base_link driven along 11 -> 12 -> 13 -> 16 by the test's TF.
    assert set_graph.call(SetRouteGraph.Request(graph_filepath=str(graph)), timeout_sec=10).success
    from zros.tf2_ros import TransformBroadcaster
    from interfaces.geometry_msgs.msg import TransformStamped
    broadcaster = TransformBroadcaster(probe)
    position = [0.0, 0.0]

    def publish() -> None:
        t = TransformStamped()
        t.header.stamp = probe.get_clock().now().to_msg()
        t.header.frame_id, t.child_frame_id = 'map', 'base_link'
        t.transform.translation.x, t.transform.translation.y = position
        t.transform.rotation.w = 1.0
        broadcaster.sendTransform(t)
    publish()
    time.sleep(0.5)
    track = ActionClient(probe, ComputeAndTrackRoute, 'compute_and_track_route')
    assert track.wait_for_server(timeout_sec=10)
    feedback: list = []
    sent = track.send_goal_async(ComputeAndTrackRoute.Goal(start_id=11, goal_id=16),
                                 feedback_callback=lambda m: feedback.append(m.feedback))
    wait_until(sent.done, 10, message='track goal response')
    got = sent.result().get_result_async()
    for x, y in [(x / 10, 0.0) for x in range(41)] + [(4.0, y / 10) for y in range(21)]:
        position[:] = [x, y]
        publish()
        time.sleep(0.03)
    wait_until(got.done, 15, message=lambda: f'tracking result\n{server.output()[-2000:]}')
    assert got.result().status == GoalStatus.STATUS_SUCCEEDED, server.output()
    # the result completes on Zenoh's thread; the last feedback, sent before it, may still wait
    # for the client's executor
    wait_until(lambda: feedback and feedback[-1].last_node_id == 16, 5,
               message=lambda: f'feedback passing node 16: {[f.last_node_id for f in feedback]}')
    assert feedback[0].rerouted and feedback[0].next_node_id == 11
    passed = [f.last_node_id for f in feedback[1:]]
    assert passed == [11, 12, 13, 16], passed
    assert [f.current_edge_id != 0 for f in feedback[1:]] == [True, True, True, False]
    assert len(feedback[1].route.nodes) == 4 and feedback[1].path.poses
    out = server.output()
    assert 'CostmapScorer' in out and 'not implemented in zros' in out


# Jazzy's nav2_params.yaml sets no graph and no dock instances: both servers still come up.
JAZZY_BRINGUP = """\
route_server:
  ros__parameters:
    boundary_radius_to_achieve_node: 1.0
    radius_to_achieve_node: 2.0
    smooth_corners: true
docking_server:
  ros__parameters:
    dock_plugins: ['simple_charging_dock']
    simple_charging_dock:
      plugin: 'opennav_docking::SimpleChargingDock'
      use_battery_status: false
"""


def test_the_lifecycle_manager_brings_up_jazzys_two_servers(spawn, probe, tmp_path):
    """As Jazzy's navigation_launch.py starts them, beside the others, under one manager."""
    from zros.action import ActionClient
    from interfaces.action_msgs.msg import GoalStatus
    from interfaces.nav2_msgs.action import ComputeRoute
    params = tmp_path / 'nav2_params.yaml'
    params.write_text(JAZZY_BRINGUP)
    route = spawn.node('nav2_route', 'route_server', '--ros-args', '--params-file', str(params))
    docking = spawn.node('opennav_docking', 'opennav_docking', '--ros-args', '-r', '__node:=docking_server',
                         '--params-file', str(params))
    manager = spawn.node('nav2_lifecycle_manager', 'lifecycle_manager', '--ros-args', '-r',
                         '__node:=lifecycle_manager_navigation', '-p', "node_names:=['route_server', 'docking_server']",
                         '-p', 'autostart:=true')
    manager.wait_for_output('Managed nodes are active', timeout=60)
    assert 'No graph file provided to load yet.' in route.output()
    assert '1 dock types and 0 dock instances' in docking.output()
    status, result = _run(ActionClient(probe, ComputeRoute, 'compute_route'), ComputeRoute.Goal(start_id=1, goal_id=2))
    assert status == GoalStatus.STATUS_ABORTED and result.error_code == ComputeRoute.Result.NO_VALID_GRAPH
    # A dock database given later, over docking_server's service; a wrong one is refused.
    from interfaces.nav2_msgs.srv import ReloadDockDatabase
    database = tmp_path / 'docks.yaml'
    database.write_text('docks:\n  home:\n    type: simple_charging_dock\n    pose: [0.5, 0.0, 0.0]\n')
    reload = probe.create_client(ReloadDockDatabase, 'docking_server/reload_database')
    assert reload.wait_for_service(timeout_sec=10)
    assert reload.call(ReloadDockDatabase.Request(filepath=str(database)), timeout_sec=10).success
    database.write_text('docks:\n  home:\n    type: other_dock\n    pose: [0.5, 0.0, 0.0]\n')
    assert not reload.call(ReloadDockDatabase.Request(filepath=str(database)), timeout_sec=10).success
    assert 'has type other_dock, which is not in dock_plugins' in docking.output()
