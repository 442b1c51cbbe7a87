"""nav2_route's route_server (Nav2 Jazzy): routes over a hand-drawn graph instead of the costmap.

    zros run nav2_route route_server --ros-args -p graph_filepath:=graph.geojson

A lifecycle node, as Nav2's: configuring loads the GeoJSON graph named by `graph_filepath` (none
yet is fine: goals then abort until `route_server/set_route_graph` gives one). Actions:

- `compute_route` (nav2_msgs/ComputeRoute): the cheapest route between two node ids, or between
  the nodes nearest two poses (`use_poses`; the start from TF when `use_start` is false), as a
  nav2_msgs/Route and a dense nav_msgs/Path (also published on `plan`).
- `compute_and_track_route`: the same, then follows the robot along it, with feedback when it
  starts and each time the robot passes a node; succeeds when it reaches the last node.

The search and the tracking are zros.navigation.route_graph's. Parameters by Nav2's names (see
docs/navigation.md for which are used and which are read and ignored: the costmap scorer, route
operations, corner smoothing and the costmap-aware nearest-node search are not implemented).
"""
from __future__ import annotations

import sys
import time
from typing import Any

import zros
from zros.executors import ExternalShutdownException, spin_nodes
from zros.lifecycle import LifecycleNode, State, TransitionCallbackReturn
from zros.navigation.node_support import Nav2Params, duration_msg, lookup_pose, path_msg, pose_in_frame
from zros.navigation.route_graph import (NoValidGraph, Route, RouteError, RouteGraph, RouteProgress, densify,
                                         distance_costs, edge_costs, find_route, load_graph, nearest_nodes,
                                         prune_ends)
from zros.navigation.servers import GoalRunner, gated_action_server, RESULT_TIMEOUT_S
from zros.tf2_ros import Buffer, TransformException, TransformListener

from interfaces.nav2_msgs.action import ComputeAndTrackRoute, ComputeRoute
from interfaces.nav2_msgs.msg import Route as RouteMsg
from interfaces.nav2_msgs.msg import RouteEdge, RouteNode
from interfaces.nav2_msgs.srv import SetRouteGraph
from interfaces.nav_msgs.msg import Path

_DISTANCE_SCORER = 'nav2_route::DistanceScorer'
# Read (so Nav2's files configure this node without complaint) but not implemented in zros.
_IGNORED = {'costmap_topic': 'global_costmap/costmap_raw',
            'enable_nn_search': True, 'max_nn_search_iterations': 10000, 'smoothing_radius': 1.0,
            'aggregate_blocked_ids': False, 'max_iterations': 0}


class RouteServer(LifecycleNode):
    def __init__(self) -> None:
        super().__init__('route_server')
        prm = Nav2Params(self)
        self.route_frame = prm.get('route_frame', 'map')
        self.base_frame = prm.get('base_frame', 'base_link')
        prm.get('global_frame', 'map')
        self.max_planning_time = prm.get('max_planning_time', 2.0)
        self.graph_filepath = prm.get('graph_filepath', '')
        prm.get('graph_file_loader', 'GeoJsonGraphFileLoader')
        self.prune_goal = prm.get('prune_goal', True)
        self.prune = {'max_dist_from_edge': prm.get('max_prune_dist_from_edge', 8.0),
                      'min_dist_from_goal': prm.get('min_prune_dist_from_goal', 0.15),
                      'min_dist_from_start': prm.get('min_prune_dist_from_start', 0.10)}
        self.num_nearest = prm.get('num_nearest_nodes', 5)
        self.density = prm.get('path_density', 0.05)
        self.smooth_corners = prm.get('smooth_corners', False)
        self.radius = prm.get('radius_to_achieve_node', 2.0)
        self.boundary_radius = prm.get('boundary_radius_to_achieve_node', 1.0)
        self.tracker_rate = prm.get('tracker_update_rate', 50.0)
        for name, default in _IGNORED.items():
            prm.get(name, default)
        self.scorers = self._read_scorers(prm)
        self.operations = prm.get('operations', [])
        for op in self.operations:
            prm.get(f'{op}.plugin', '')
        result_timeout = prm.get('action_server_result_timeout', RESULT_TIMEOUT_S)
        prm.report_unused()
        self.graph: RouteGraph | None = None
        self.costs: Any = None
        self.tf_buffer = Buffer(node=self)
        self.tf_listener = TransformListener(self.tf_buffer, self)
        self.plan_pub = self.create_lifecycle_publisher(Path, 'plan', 10)
        self.goals = GoalRunner(self)
        gated_action_server(self, ComputeRoute, 'compute_route', self._compute, result_timeout=result_timeout)
        gated_action_server(self, ComputeAndTrackRoute, 'compute_and_track_route', self._compute_and_track,
                            result_timeout=result_timeout)
        self.create_service(SetRouteGraph, '~/set_route_graph', self._set_graph)

    def _read_scorers(self, prm: Nav2Params) -> list[tuple[float, str]]:
        """(weight, speed tag) of each DistanceScorer in `edge_cost_functions`; other scorers are
        said once and skipped (their share of an edge's cost is 0)."""
        scorers = []
        for sid in prm.get('edge_cost_functions', ['DistanceScorer', 'DynamicEdgesScorer']):
            plugin = prm.get(f'{sid}.plugin', f'nav2_route::{sid}')
            if plugin.replace('/', '::') == _DISTANCE_SCORER:
                scorers.append((prm.get(f'{sid}.weight', 1.0), prm.get(f'{sid}.speed_tag', 'speed_limit')))
            else:
                self.get_logger().info(f'Edge scorer {sid} ({plugin}) is not implemented in zros: skipped')
        return scorers

    def on_configure(self, state: State) -> TransitionCallbackReturn:
        if self.smooth_corners:
            self.get_logger().info('smooth_corners: corner arcs are not implemented in zros; '
                                   'the path turns on the nodes')
        if not self.graph_filepath:
            self.get_logger().info('No graph file provided to load yet.')
            return TransitionCallbackReturn.SUCCESS
        try:
            self._load(self.graph_filepath)
        except NoValidGraph as exc:
            self.get_logger().error(f'Failed to configure route server: {exc}')
            return TransitionCallbackReturn.FAILURE
        return TransitionCallbackReturn.SUCCESS

    def _load(self, path: str) -> None:
        self.get_logger().info(f'Loading graph file from {path}')
        graph = load_graph(path)
        other = sorted({f for f in graph.node_frames if f and f != self.route_frame})
        if other:
            raise NoValidGraph(f'nodes in frame {", ".join(other)}: zros reads graphs in the route frame '
                               f'({self.route_frame}) only')
        scored = None
        if self.scorers:
            scored = sum(distance_costs(graph, weight=w, speed_tag=tag) for w, tag in self.scorers)
        self.costs = edge_costs(graph, scored)
        self.graph = graph
        self.get_logger().info(f'Route graph: {len(graph.node_ids)} nodes, {len(graph.edge_ids)} edges')

    def _set_graph(self, request: Any, response: Any) -> Any:
        self.get_logger().info(f'Setting new route graph: {request.graph_filepath}.')
        try:
            self._load(request.graph_filepath)
            response.success = True
        except NoValidGraph as exc:
            self.get_logger().warn(f'Failed to set new route graph: {exc}')
            response.success = False
        return response

    # -- goals ---------------------------------------------------------------------------------
    def _plan(self, goal: Any) -> tuple[Route, tuple[float, float] | None]:
        """The route a goal asks for, its ends pruned as Nav2 does; and the start's xy if from poses."""
        graph = self.graph
        if graph is None:
            raise NoValidGraph('No graph set! Aborting request.')
        if not goal.use_poses:
            return find_route(graph, graph.index_of(goal.start_id), graph.index_of(goal.goal_id), self.costs), None
        try:
            if goal.use_start:
                sx, sy, _ = pose_in_frame(self.tf_buffer, goal.start, self.route_frame)
            else:
                sx, sy, _ = lookup_pose(self.tf_buffer, self.route_frame, self.base_frame)
            gx, gy, _ = pose_in_frame(self.tf_buffer, goal.goal, self.route_frame)
        except TransformException as exc:
            raise _TfError(f'Failed to obtain the start or goal pose in {self.route_frame}: {exc}') from None
        start = int(nearest_nodes(graph, (sx, sy))[0])
        end = int(nearest_nodes(graph, (gx, gy))[0])
        route = find_route(graph, start, end, self.costs)
        route = prune_ends(graph, route, self.costs, (sx, sy), (gx, gy) if self.prune_goal else None, **self.prune)
        return route, (sx, sy)

    def _messages(self, route: Route) -> tuple[Any, Any]:
        """nav2_msgs/Route and the dense nav_msgs/Path of a route, stamped now in the route frame."""
        graph = self.graph
        stamp = self.get_clock().now().to_msg()
        msg = RouteMsg()
        msg.header.frame_id, msg.header.stamp = self.route_frame, stamp
        msg.route_cost = route.cost
        nodes = []
        for i in route.nodes:
            node = RouteNode(nodeid=int(graph.node_ids[i]))
            node.position.x, node.position.y = map(float, graph.xy[i])
            nodes.append(node)
        edges = []
        for e in route.edges:
            edge = RouteEdge(edgeid=int(graph.edge_ids[e]))
            edge.start.x, edge.start.y = map(float, graph.xy[graph.edge_start[e]])
            edge.end.x, edge.end.y = map(float, graph.xy[graph.edge_end[e]])
            edges.append(edge)
        msg.nodes, msg.edges = nodes, edges
        points, yaws = densify(graph, route, self.density)
        path = path_msg(points, yaws, self.route_frame, stamp)
        self.plan_pub.publish(path)
        return msg, path

    def _fail(self, handle: Any, result: Any, exc: Exception) -> Any:
        goal = handle.request
        code = getattr(type(result), getattr(exc, 'code', 'UNKNOWN'), type(result).UNKNOWN)
        where = (f'Start: [({goal.start.pose.position.x:.2f}, {goal.start.pose.position.y:.2f}) / {goal.start_id}] '
                 f'Goal: [({goal.goal.pose.position.x:.2f}, {goal.goal.pose.position.y:.2f}) / {goal.goal_id}]')
        return self.goals.fail(handle, result, code, f'Route server failed on request: {where}: "{exc}"')

    def _compute(self, handle: Any) -> Any:
        self.get_logger().info('Computing route to goal.')
        result = ComputeRoute.Result()
        started = time.monotonic()
        try:
            route, _ = self._plan(handle.request)
        except RouteError as exc:
            return self._fail(handle, result, exc)
        self.get_logger().info(f'Route found with {len(route.nodes)} nodes and {len(route.edges)} edges')
        result.route, result.path = self._messages(route)
        elapsed = time.monotonic() - started
        if self.max_planning_time > 0.0 and elapsed > self.max_planning_time:
            self.get_logger().warn(f'Route planner missed its desired rate of {1 / self.max_planning_time:.4f} Hz')
        result.planning_time = duration_msg(elapsed)
        handle.succeed()
        return result

    def _compute_and_track(self, handle: Any) -> Any:
        self.get_logger().info('Computing and tracking route to goal.')
        result = ComputeAndTrackRoute.Result()
        started = time.monotonic()
        self.goals.slot.take(handle)
        try:
            route, _ = self._plan(handle.request)
        except RouteError as exc:
            self.goals.slot.release(handle)
            return self._fail(handle, result, exc)
        route_msg, path = self._messages(route)
        progress = RouteProgress(self.graph, route, radius=self.radius, boundary_radius=self.boundary_radius)
        ids = self.graph

        def feedback(rerouted: bool) -> None:
            fb = ComputeAndTrackRoute.Feedback(rerouted=rerouted)
            fb.route, fb.path = route_msg, path
            fb.last_node_id = int(ids.node_ids[progress.last_node]) if progress.last_node is not None else 0
            fb.next_node_id = int(ids.node_ids[progress.next_node]) if progress.next_node is not None else 0
            edge = progress.current_edge
            fb.current_edge_id = int(ids.edge_ids[edge]) if edge is not None else 0
            handle.publish_feedback(fb)
        feedback(True)

        def step() -> Any:
            try:
                x, y, _ = lookup_pose(self.tf_buffer, self.route_frame, self.base_frame)
            except TransformException as exc:
                return self._fail(handle, result, _TfError(f'Unable to get robot pose in {self.route_frame}: {exc}'))
            if not progress.update((x, y)):
                return None
            if progress.done:
                self.get_logger().info('Routing to goal completed!')
                feedback(False)
                result.execution_duration = duration_msg(time.monotonic() - started)
                handle.succeed()
                return result
            feedback(False)
            return None
        return self.goals.loop(handle, result, self.tracker_rate, step)


class _TfError(RouteError):
    code = 'TF_ERROR'


def main(args: list[str] | None = None) -> int:
    try:
        with zros.init(args=args):
            spin_nodes(RouteServer())
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    return 0


if __name__ == '__main__':
    sys.exit(main())
