"""Navigation end to end over real processes: the simulator in a small room, the map from the
world's exact raster, map -> odom from the simulator's ground truth (perfect localization), and nav2_bringup's
navigation_launch.py (planner, controller, behaviors, bt_navigator, waypoint follower, lifecycle
manager). Goals go through navigate_to_pose, navigate_through_poses, follow_waypoints and
goal_pose, as a user's would; the simulator's ground truth says where the robot really is."""
from __future__ import annotations

import math
import sys
import threading
import time
from pathlib import Path
from typing import Any

import pytest

from conftest import wait_until

WORLD = """
name: nav_room
spawn: {x: -1.0, y: -1.0, yaw: 0.0}
obstacles:
- ring: {center: [0, 0], sides: 4, inner_circumradius: 2.55, outer_circumradius: 2.83}
- box: {center: [0.3, 0.0], size: [0.4, 1.6], yaw: 0.0}
"""


@pytest.fixture(scope='module')
def stack(module_spawn: Any, tmp_path_factory: Any) -> Any:
    from zros.executors import ExternalShutdownException, MultiThreadedExecutor
    from zros.node import Node
    from zros.qos import DurabilityPolicy, QoSProfile
    from zros.sim import parse_world, rasterize
    from interfaces.nav_msgs.msg import OccupancyGrid
    world_file = tmp_path_factory.mktemp('world') / 'nav_room.yaml'
    world_file.write_text(WORLD)
    # Encoder odometry, as the real robot's: held in place by teleports (the stuck-robot test), it
    # still counts its wheels turning, so the spin recovery ends (world odometry would undo each turn).
    module_spawn.node('turtlebot3_gazebo', 'gzserver', '--ros-args', '-p', f'world:={world_file}',
                      '-p', 'real_time_factor:=3.0', '-p', 'odometry_source:=encoder')
    from zros.ament_index_python.packages import get_package_share_directory
    burger = Path(get_package_share_directory('turtlebot3_navigation2')) / 'param' / 'burger.yaml'
    launch = module_spawn.command(sys.executable, '-m', 'zros', 'launch', 'nav2_bringup', 'navigation_launch.py',
                                  'use_sim_time:=True', f'params_file:={burger}', name='navigation')
    from zros.context import Context
    context = Context().init([], install_signal_handlers=False)
    node = Node('nav_test', context=context)
    raster = rasterize(parse_world(WORLD), 0.05)
    grid = OccupancyGrid()
    grid.header.frame_id = 'map'
    grid.info.resolution = 0.05
    grid.info.height, grid.info.width = raster.cells.shape
    grid.info.origin.position.x, grid.info.origin.position.y = map(float, raster.origin)
    grid.data = raster.occupancy_data()
    map_pub = node.create_publisher(OccupancyGrid, '/map', QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL))
    map_pub.publish(grid)
    truth: dict[str, Any] = {}
    _perfect_localization(node, truth)
    executor = MultiThreadedExecutor(num_threads=4, context=context)
    executor.add_node(node)

    def spin() -> None:
        try:
            executor.spin()
        except ExternalShutdownException:
            pass   # the context went down before the executor noticed its own shutdown
    threading.Thread(target=spin, daemon=True).start()
    from zros.lifecycle import LifecycleClient
    nav = LifecycleClient(node, 'bt_navigator')

    def active() -> bool:
        try:
            return nav.wait_for_services(timeout_sec=0.5) and nav.get_state().label == 'active'
        except Exception:  # noqa: BLE001 - not up yet
            return False
    wait_until(active, 180, interval=0.5, message=lambda: f'bt_navigator active\n{launch.output()[-3000:]}')

    class Stack:
        pass
    s = Stack()
    s.node, s.launch, s.truth, s.executor = node, launch, truth, executor
    yield s
    executor.shutdown(timeout_sec=2)
    context.shutdown()


def _perfect_localization(node: Any, truth: dict) -> None:
    """AMCL's role with no error: map -> odom = (world -> robot) * (odom -> robot)^-1, from the
    simulator's ground truth and odometry of the same instant (the world frame is the map's)."""
    from zros.navigation.node_support import yaw_of
    from zros.tf2_ros import TransformBroadcaster
    from interfaces.geometry_msgs.msg import TransformStamped
    from interfaces.nav_msgs.msg import Odometry
    broadcaster = TransformBroadcaster(node)
    odom: dict[int, Any] = {}

    def pose2d(msg: Any) -> tuple[float, float, float]:
        p = msg.pose.pose
        return p.position.x, p.position.y, yaw_of(p.orientation)

    def stamp(msg: Any) -> int:
        return msg.header.stamp.sec * 1_000_000_000 + msg.header.stamp.nanosec

    def on_odom(msg: Any) -> None:
        odom.clear()
        odom[stamp(msg)] = pose2d(msg)

    def on_truth(msg: Any) -> None:
        truth['pose'] = msg.pose.pose
        o = odom.get(stamp(msg))
        if o is None:
            return
        wx, wy, wyaw = pose2d(msg)
        yaw = wyaw - o[2]
        c, s = math.cos(yaw), math.sin(yaw)
        t = TransformStamped()
        t.header.stamp, t.header.frame_id, t.child_frame_id = msg.header.stamp, 'map', 'odom'
        t.transform.translation.x = wx - (c * o[0] - s * o[1])
        t.transform.translation.y = wy - (s * o[0] + c * o[1])
        t.transform.rotation.z, t.transform.rotation.w = math.sin(yaw / 2), math.cos(yaw / 2)
        broadcaster.sendTransform(t)
    node.create_subscription(Odometry, '/odom', on_odom, 10)
    node.create_subscription(Odometry, '/sim/ground_truth', on_truth, 10)


def _pose(x: float, y: float, yaw: float = 0.0) -> Any:
    from interfaces.geometry_msgs.msg import PoseStamped
    p = PoseStamped()
    p.header.frame_id = 'map'
    p.pose.position.x, p.pose.position.y = x, y
    p.pose.orientation.z, p.pose.orientation.w = math.sin(yaw / 2), math.cos(yaw / 2)
    return p


def _send(stack: Any, action: type, name: str, goal: Any, feedback: list | None = None) -> Any:
    from zros.action import ActionClient
    client = ActionClient(stack.node, action, name)
    assert client.wait_for_server(timeout_sec=10)
    future = client.send_goal_async(goal, feedback_callback=(lambda m: feedback.append(m.feedback)) if feedback is not None else None)
    handle = wait_until(lambda: future.result() if future.done() else None, 10, message='goal accepted')
    assert handle.accepted
    return handle


def _result(handle: Any, timeout: float) -> Any:
    future = handle.get_result_async()
    return wait_until(lambda: future.result() if future.done() else None, timeout, message='result')


def _truth_xy(stack: Any) -> tuple[float, float]:
    p = stack.truth['pose'].position
    return p.x, p.y


def test_goal_is_reached_with_feedback(stack: Any) -> None:
    from interfaces.action_msgs.msg import GoalStatus
    from interfaces.nav2_msgs.action import NavigateToPose
    feedback: list = []
    handle = _send(stack, NavigateToPose, 'navigate_to_pose', NavigateToPose.Goal(pose=_pose(1.4, 0.8, 1.57)), feedback)
    response = _result(handle, 120)
    assert response.status == GoalStatus.STATUS_SUCCEEDED, stack.launch.output()[-3000:]
    x, y = _truth_xy(stack)
    assert math.hypot(x - 1.4, y - 0.8) < 0.35
    assert feedback, 'feedback published'
    assert max(f.distance_remaining for f in feedback) > 1.0
    assert any(f.estimated_time_remaining.sec > 0 for f in feedback)
    assert feedback[-1].navigation_time.sec > 0 and feedback[-1].current_pose.header.frame_id == 'map'


def test_the_local_costmap_publishes_the_footprint_a_collision_monitor_takes(stack: Any) -> None:
    """nav2_bringup's collision_monitor zone reads /local_costmap/published_footprint: the robot's
    circle (burger.yaml's robot_radius, 0.1 m) at its pose, in the costmap's frame."""
    from interfaces.geometry_msgs.msg import PolygonStamped
    got: list = []
    sub = stack.node.create_subscription(PolygonStamped, '/local_costmap/published_footprint', got.append, 1)
    try:
        wait_until(lambda: got, 20, message='no published_footprint within 20 s')
    finally:
        stack.node.destroy_subscription(sub)
    msg = got[-1]
    assert msg.header.frame_id == 'odom' and len(msg.polygon.points) == 16
    xs = [p.x for p in msg.polygon.points]
    assert max(xs) - min(xs) == pytest.approx(2 * 0.1, abs=0.01)


def test_goal_in_a_wall_fails_with_goal_occupied(stack: Any) -> None:
    from interfaces.action_msgs.msg import GoalStatus
    from interfaces.nav2_msgs.action import ComputePathToPose, NavigateToPose
    handle = _send(stack, NavigateToPose, 'navigate_to_pose', NavigateToPose.Goal(pose=_pose(0.3, 0.0)))
    response = _result(handle, 30)
    assert response.status == GoalStatus.STATUS_ABORTED
    assert response.result.error_code == ComputePathToPose.Result.GOAL_OCCUPIED
    assert 'lethal' in response.result.error_msg


def test_cancel_stops_the_robot_and_a_new_goal_preempts(stack: Any) -> None:
    from interfaces.action_msgs.msg import GoalStatus
    from interfaces.nav2_msgs.action import NavigateToPose
    first = _send(stack, NavigateToPose, 'navigate_to_pose', NavigateToPose.Goal(pose=_pose(-1.5, 1.5)))
    wait_until(lambda: math.hypot(*(a - b for a, b in zip(_truth_xy(stack), (1.4, 0.8)))) > 0.3, 30,
               message='robot moving')
    second = _send(stack, NavigateToPose, 'navigate_to_pose', NavigateToPose.Goal(pose=_pose(-1.5, -1.5)))
    assert _result(first, 10).status == GoalStatus.STATUS_ABORTED
    wait_until(lambda: math.hypot(_truth_xy(stack)[0] + 1.5, _truth_xy(stack)[1] + 1.5) < 1.5, 60,
               message='heading for the second goal')
    cancel = second.cancel_goal_async()
    wait_until(lambda: cancel.done(), 10)
    assert _result(second, 10).status == GoalStatus.STATUS_CANCELED
    time.sleep(1.0)
    before = _truth_xy(stack)
    time.sleep(1.0)
    after = _truth_xy(stack)
    assert math.hypot(after[0] - before[0], after[1] - before[1]) < 0.02, 'the robot stopped'


def test_waypoints_report_missed_ones(stack: Any) -> None:
    from interfaces.action_msgs.msg import GoalStatus
    from interfaces.nav2_msgs.action import FollowWaypoints
    feedback: list = []
    goal = FollowWaypoints.Goal(poses=[_pose(-1.0, 0.0), _pose(0.3, 0.0), _pose(-1.0, -1.2)])
    handle = _send(stack, FollowWaypoints, 'follow_waypoints', goal, feedback)
    response = _result(handle, 150)
    assert response.status == GoalStatus.STATUS_SUCCEEDED, stack.launch.output()[-3000:]
    assert list(response.result.missed_waypoints) == [1]
    assert {f.current_waypoint for f in feedback} == {0, 1, 2}
    x, y = _truth_xy(stack)
    assert math.hypot(x + 1.0, y + 1.2) < 0.35


def test_goal_pose_topic_drives_the_robot(stack: Any) -> None:
    """What RViz's "Nav2 Goal" button does: one PoseStamped on /goal_pose."""
    from interfaces.geometry_msgs.msg import PoseStamped
    pub = stack.node.create_publisher(PoseStamped, '/goal_pose', 10)
    try:
        assert pub.wait_for_subscribers(1, timeout_sec=10), 'bt_navigator subscribes to /goal_pose'
        # A message sent the instant the match is seen can still be lost on the way (as with
        # `zros topic pub --once`): publish again until bt_navigator says it got it.
        wait_until(lambda: pub.publish(_pose(-1.0, 1.0, 1.57)) or 'Received goal_pose (-1.00, 1.00)' in
                   stack.launch.output(), 20, interval=2.0, message='bt_navigator received goal_pose')
        wait_until(lambda: math.hypot(_truth_xy(stack)[0] + 1.0, _truth_xy(stack)[1] - 1.0) < 0.35, 90,
                   message=lambda: f'robot at the goal_pose goal\n{stack.launch.output()[-3000:]}')
    finally:
        stack.node.destroy_publisher(pub)


def test_navigate_through_poses_reaches_the_last_pose_with_feedback(stack: Any) -> None:
    from interfaces.action_msgs.msg import GoalStatus
    from interfaces.nav2_msgs.action import NavigateThroughPoses
    feedback: list = []
    goal = NavigateThroughPoses.Goal(poses=[_pose(0.9, -0.9), _pose(1.0, 0.8, 1.57)])
    handle = _send(stack, NavigateThroughPoses, 'navigate_through_poses', goal, feedback)
    response = _result(handle, 150)
    assert response.status == GoalStatus.STATUS_SUCCEEDED, stack.launch.output()[-3000:]
    x, y = _truth_xy(stack)
    assert math.hypot(x - 1.0, y - 0.8) < 0.35
    remaining = [f.number_of_poses_remaining for f in feedback]
    assert remaining[0] == 2 and remaining[-1] == 1, remaining        # the first pose was passed
    assert feedback[0].distance_remaining > feedback[-1].distance_remaining
    assert feedback[-1].current_pose.header.frame_id == 'map'


def test_a_stuck_robot_runs_the_recoveries_then_reaches_its_goal(stack: Any) -> None:
    """Hold the robot where it is (teleporting it back, as a blocked wheel would): the progress
    checker fails, bt_navigator clears the costmaps and then spins; let go and the goal succeeds."""
    from interfaces.action_msgs.msg import GoalStatus
    from interfaces.gazebo_msgs.srv import SetEntityState
    from interfaces.nav2_msgs.action import NavigateToPose
    teleport = stack.node.create_client(SetEntityState, '/set_entity_state')
    assert teleport.wait_for_service(timeout_sec=10)
    held = SetEntityState.Request()
    held.state.name = 'burger'
    held.state.pose = stack.truth['pose']
    holding = threading.Event()
    holding.set()

    def hold() -> None:
        while holding.is_set():
            teleport.call_async(held)
            time.sleep(0.05)
    holder = threading.Thread(target=hold, daemon=True)
    holder.start()
    feedback: list = []
    try:
        handle = _send(stack, NavigateToPose, 'navigate_to_pose', NavigateToPose.Goal(pose=_pose(-1.0, -0.9)), feedback)
        wait_until(lambda: any(f.number_of_recoveries >= 2 for f in feedback), 90,
                   message=lambda: f'two recoveries\n{stack.launch.output()[-3000:]}')
    finally:
        holding.clear()
        holder.join(timeout=5)
    response = _result(handle, 120)
    assert response.status == GoalStatus.STATUS_SUCCEEDED, stack.launch.output()[-3000:]
    out = stack.launch.output()
    assert 'Failed to make progress' in out and 'Turning 1.57 for spin behavior.' in out
    x, y = _truth_xy(stack)
    assert math.hypot(x + 1.0, y + 0.9) < 0.35
    stack.node.destroy_client(teleport)


MISSION = '''
import sys
import zros
from zros.nav2_simple_commander.robot_navigator import BasicNavigator, TaskResult
from interfaces.geometry_msgs.msg import PoseStamped

zros.init()
navigator = BasicNavigator()
start = PoseStamped()
start.header.frame_id = 'map'
start.header.stamp = navigator.get_clock().now().to_msg()
start.pose.position.x, start.pose.position.y = -1.0, -1.2
start.pose.orientation.w = 1.0
navigator.setInitialPose(start)
# No amcl in this stack (the test gives map -> odom): the default wait says so and,
# with a timeout, gives up; then wait for the navigator alone.
print('default wait:', navigator.waitUntilNav2Active(timeout=2.0), flush=True)
assert navigator.waitUntilNav2Active(localizer='')
# Jazzy's name for a localizer that is no lifecycle node (robot_localization's EKF, GPS): not asked
assert navigator.waitUntilNav2Active(localizer='robot_localization', timeout=30.0)
goal = PoseStamped()
goal.header.frame_id = 'map'
# Between four pillars, 0.6 m clear of each (a goal a few cm from a pillar is lethal as soon as
# the scans mark the pillar a cell off, as Nav2's planner would also say).
goal.pose.position.x, goal.pose.position.y = -0.55, 0.55
goal.pose.orientation.w = 1.0
print('plan poses:', len(navigator.getPath(start, goal, use_start=True).poses), flush=True)
navigator.goToPose(goal)
seen = 0
while not navigator.isTaskComplete():
    feedback = navigator.getFeedback()
    if feedback is not None:
        seen += 1
print('feedback:', seen > 0, 'result:', navigator.getResult().name, flush=True)
navigator.clearAllCostmaps()
print('costmap:', navigator.getGlobalCostmap().metadata.size_x > 0, flush=True)
sys.exit(0 if navigator.getResult() == TaskResult.SUCCEEDED else 1)
'''


def test_basic_navigator_mission_script(stack: Any, module_spawn: Any) -> None:
    script = module_spawn.script(MISSION, name='mission')
    code = script.wait(180)
    out = script.output()
    assert code == 0, out + '\n--- the stack:\n' + stack.launch.output()[-4000:]
    assert 'amcl is not running (no amcl/get_state service)' in out and 'default wait: False' in out
    assert 'Nav2 is ready for use!' in out
    assert 'feedback: True result: SUCCEEDED' in out and 'costmap: True' in out
    x, y = _truth_xy(stack)
    assert math.hypot(x + 0.55, y - 0.55) < 0.35


def test_navigation_from_text_example_node(stack: Any, module_spawn: Any, tmp_path: Any) -> None:
    goals = tmp_path / 'goals.txt'
    goals.write_text('# x y w\n-1.0 0.0 1.0\n0.3 0.0 1.0\n')
    node = module_spawn.node('navigation_from_text', 'navigation_from_text', '--ros-args',
                             '-p', f'goals_file:={goals}', '-p', "wait_for:=['bt_navigator']")
    assert node.wait(150) == 0, node.output()
    out = node.output()
    assert out.count('Goal succeeded!') == 1 and out.count('Goal failed!') == 1, out
    assert 'All the 2 goals processed' in out


ASSISTED_TELEOP = '''
import sys
import time

import rclpy
from geometry_msgs.msg import Twist
from nav2_simple_commander.robot_navigator import BasicNavigator, TaskResult
from std_msgs.msg import Empty

rclpy.init()
navigator = BasicNavigator()
teleop = navigator.create_publisher(Twist, 'cmd_vel_teleop', 10)
preempt = navigator.create_publisher(Empty, 'preempt_teleop', 10)
print('accepted:', navigator.assistedTeleop(time_allowance=60), flush=True)
command = Twist()
command.angular.z = 0.6
end = time.monotonic() + 3.0
while time.monotonic() < end:
    teleop.publish(command)
    rclpy.spin_once(navigator, timeout_sec=0.1)
preempt.publish(Empty())
while not navigator.isTaskComplete():
    preempt.publish(Empty())
print('result:', navigator.getResult().name, flush=True)
from geometry_msgs.msg import PoseStamped
navigator.clearCostmapAroundRobot(1.0)
navigator.clearCostmapExceptRegion(3.0)
pose = PoseStamped()
pose.header.frame_id = 'map'
navigator.clearCostmapAroundPose(pose, 0.5)
print('cleared: Jazzy', flush=True)
sys.exit(0)
'''


def test_assisted_teleop_passes_the_teleop_command_until_preempted(stack: Any, module_spawn: Any,
                                                                   tmp_path: Any) -> None:
    """BasicNavigator.assistedTeleop, unmodified rclpy: a turn on cmd_vel_teleop reaches the
    robot through the behavior server; preempt_teleop ends the task as succeeded. Then Jazzy's
    costmap clearers answer."""
    from zros.navigation.node_support import yaw_of
    before = yaw_of(stack.truth['pose'].orientation)
    path = tmp_path / 'assisted_teleop.py'
    path.write_text(ASSISTED_TELEOP)
    script = module_spawn.command(sys.executable, '-m', 'zros', 'python', str(path), name='assisted_teleop')
    assert script.wait(90) == 0, script.output()
    out = script.output()
    assert 'accepted: True' in out and 'result: SUCCEEDED' in out and 'cleared: Jazzy' in out, out
    turned = abs(math.remainder(yaw_of(stack.truth['pose'].orientation) - before, math.tau))
    assert turned > 0.5, (turned, out)


def test_a_path_into_a_wall_stops_the_robot_then_runs_out_of_patience(stack: Any) -> None:
    """FollowPath straight through the box: the controller sees the collision ahead, stops the
    robot short of it and asks again each period; after burger.yaml's failure_tolerance (0.3 s)
    of that, the goal aborts with NO_VALID_CONTROL, and the robot has not touched the box."""
    import numpy as np
    from interfaces.action_msgs.msg import GoalStatus
    from interfaces.nav2_msgs.action import FollowPath, NavigateToPose
    from zros.navigation.node_support import path_msg
    from zros.navigation.planner import path_yaws
    side = -1.0 if _truth_xy(stack)[0] < 0.3 else 1.0    # the box spans x 0.1..0.5: stay on the robot's side
    start = (0.3 + side, 0.0)
    facing = 0.0 if side < 0 else math.pi
    handle = _send(stack, NavigateToPose, 'navigate_to_pose', NavigateToPose.Goal(pose=_pose(*start, facing)))
    assert _result(handle, 120).status == GoalStatus.STATUS_SUCCEEDED, stack.launch.output()[-3000:]
    line = np.linspace(start, (0.3 - side, 0.0), 41)
    path = path_msg(line, path_yaws(line, facing), 'map', stack.node.get_clock().now().to_msg())
    handle = _send(stack, FollowPath, 'follow_path', FollowPath.Goal(path=path))
    response = _result(handle, 90)
    assert response.status == GoalStatus.STATUS_ABORTED, stack.launch.output()[-3000:]
    assert response.result.error_code == 106 and 'patience' in response.result.error_msg, response.result.error_msg
    x, _ = _truth_xy(stack)
    assert abs(x - 0.3) > 0.2 + 0.105, x                # the box's face plus the burger's radius


def test_a_dead_controller_is_reported_by_the_manager(stack: Any) -> None:
    """Last in this module: it takes the stack down."""
    import os
    import re
    import signal
    pid = int(re.search(r'\[controller_server-\d+\]: process started with pid \[(\d+)\]', stack.launch.output()).group(1))
    os.kill(pid, signal.SIGKILL)
    wait_until(lambda: 'CRITICAL FAILURE: SERVER controller_server IS DOWN' in stack.launch.output(), 20,
               message=lambda: stack.launch.output()[-2000:])
    from zros.errors import ServiceCallError
    from zros.lifecycle import LifecycleClient
    bt_navigator = LifecycleClient(stack.node, 'bt_navigator')

    def bt_navigator_reset() -> bool:
        try:
            return bt_navigator.get_state(timeout_sec=5.0).label != 'active'
        except ServiceCallError:       # busy in the manager's deactivate/cleanup on a loaded machine: ask again
            return False
    wait_until(bt_navigator_reset, 30, message='the rest of the stack reset')
