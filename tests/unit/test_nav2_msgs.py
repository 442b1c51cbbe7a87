"""nav2_msgs and map_msgs keep ROS 2's field layout, so programs written against Nav2 run unchanged."""
from interfaces.map_msgs.msg import OccupancyGridUpdate
from interfaces.nav2_msgs.action import (
    ComputePathToPose, FollowPath, FollowWaypoints, NavigateThroughPoses, NavigateToPose, Spin)
from interfaces.nav2_msgs.msg import Costmap, ParticleCloud
from interfaces.nav2_msgs.srv import ClearEntireCostmap, LoadMap


def _fields(cls) -> list[str]:
    return list(cls.get_fields_and_field_types())


def test_humble_layout_with_iron_error_codes():
    assert _fields(NavigateToPose.Goal) == ['pose', 'behavior_tree']
    assert _fields(NavigateToPose.Feedback) == [
        'current_pose', 'navigation_time', 'estimated_time_remaining', 'number_of_recoveries',
        'distance_remaining']
    assert _fields(NavigateThroughPoses.Feedback)[-1] == 'number_of_poses_remaining'
    # Humble's result fields come first; Iron's error_code/error_msg follow.
    assert _fields(NavigateToPose.Result) == ['result', 'error_code', 'error_msg']
    assert _fields(FollowWaypoints.Result) == ['missed_waypoints', 'error_code', 'error_msg']
    assert _fields(ComputePathToPose.Goal) == ['goal', 'start', 'planner_id', 'use_start']
    assert ComputePathToPose.Result.GOAL_OCCUPIED == 206
    assert ComputePathToPose.Result.NO_VALID_PATH == 208
    assert FollowPath.Result.FAILED_TO_MAKE_PROGRESS == 105
    assert Spin.Result.COLLISION_AHEAD == 703


def test_messages_and_services():
    assert _fields(Costmap) == ['header', 'metadata', 'data']
    assert _fields(ParticleCloud) == ['header', 'particles']
    assert _fields(ClearEntireCostmap.Request) == ['request']
    assert LoadMap.Response.RESULT_MAP_DOES_NOT_EXIST == 1
    assert _fields(OccupancyGridUpdate) == ['header', 'x', 'y', 'width', 'height', 'data']


def test_jazzy_route_and_docking_layout():
    from interfaces.nav2_msgs.action import ComputeAndTrackRoute, ComputeRoute, DockRobot, UndockRobot
    from interfaces.nav2_msgs.msg import Route, RouteEdge, RouteNode
    assert _fields(ComputeRoute.Goal) == ['start_id', 'start', 'goal_id', 'goal', 'use_start', 'use_poses']
    assert _fields(ComputeRoute.Result) == ['planning_time', 'path', 'route', 'error_code']
    assert _fields(ComputeAndTrackRoute.Feedback) == [
        'last_node_id', 'next_node_id', 'current_edge_id', 'route', 'path', 'operations_triggered', 'rerouted']
    assert ComputeRoute.Result.NO_VALID_ROUTE == 405 and ComputeAndTrackRoute.Result.OPERATION_FAILED == 406
    assert _fields(Route) == ['header', 'route_cost', 'nodes', 'edges']
    assert _fields(RouteNode) == ['nodeid', 'position'] and _fields(RouteEdge) == ['edgeid', 'start', 'end']
    goal = DockRobot.Goal()
    assert goal.use_dock_id and goal.navigate_to_staging_pose and goal.max_staging_time == 1000.0
    assert _fields(DockRobot.Result) == ['success', 'error_code', 'num_retries', 'error_msg']
    assert DockRobot.Result.FAILED_TO_CHARGE == 906 and DockRobot.Feedback.WAIT_FOR_CHARGE == 4
    assert UndockRobot.Goal().max_undocking_time == 30.0 and UndockRobot.Result().success
