"""nav2_simple_commander's BasicNavigator: a Python API for Nav2 tasks (Humble's methods and
semantics), for mission scripts:

    from zros.nav2_simple_commander.robot_navigator import BasicNavigator, TaskResult
    navigator = BasicNavigator()
    navigator.setInitialPose(initial_pose)
    navigator.waitUntilNav2Active()
    navigator.goToPose(goal_pose)
    while not navigator.isTaskComplete():
        feedback = navigator.getFeedback()
    if navigator.getResult() == TaskResult.SUCCEEDED: ...

One difference, deliberate: `waitUntilNav2Active` never waits silently. Every few seconds it
logs which node is not active yet and why (not running, still unconfigured, amcl without an
initial pose, no amcl at all because SLAM localizes), and it takes an optional `timeout` [s].
"""
from __future__ import annotations

import time
from enum import Enum
from typing import Any

import zros
from zros.action import ActionClient
from zros.duration import Duration
from zros.node import Node
from zros.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy

from interfaces.action_msgs.msg import GoalStatus
from interfaces.geometry_msgs.msg import PoseWithCovarianceStamped
from interfaces.lifecycle_msgs.srv import GetState
from interfaces.nav2_msgs.action import (AssistedTeleop, BackUp, ComputePathThroughPoses, ComputePathToPose,
                                         DockRobot, DriveOnHeading, FollowGPSWaypoints, FollowPath, FollowWaypoints,
                                         NavigateThroughPoses, NavigateToPose, SmoothPath, Spin, UndockRobot)
from interfaces.nav2_msgs.srv import (ClearCostmapAroundPose, ClearCostmapAroundRobot, ClearCostmapExceptRegion,
                                      ClearEntireCostmap, GetCostmap, LoadMap, ManageLifecycleNodes)

__all__ = ['BasicNavigator', 'TaskResult']

_REPORT_PERIOD_S = 3.0


class TaskResult(Enum):
    """How a navigator task ended, as `getResult()` reports it."""
    UNKNOWN = 0
    SUCCEEDED = 1
    CANCELED = 2
    FAILED = 3


class BasicNavigator(Node):
    """A node that drives Nav2's action servers and services from a plain script.

    Every method blocks the calling thread while it spins this node itself, so a mission
    script needs no executor of its own (and must not spin this node elsewhere). Methods keep
    Nav2 Humble's camelCase names so that scripts written for it run unchanged.

    :param node_name: The node's name.
    :param namespace: The robot's namespace: Nav2's servers are looked up under it.
    """
    def __init__(self, node_name: str = 'basic_navigator', namespace: str = '') -> None:
        super().__init__(node_name=node_name, namespace=namespace)
        self.initial_pose: Any = None
        self.initial_pose_received = False
        self.goal_handle: Any = None
        self.result_future: Any = None
        self.feedback: Any = None
        self.status: Any = None
        amcl_pose_qos = QoSProfile(durability=DurabilityPolicy.TRANSIENT_LOCAL, reliability=ReliabilityPolicy.RELIABLE,
                                   history=HistoryPolicy.KEEP_LAST, depth=1)
        self.nav_through_poses_client = ActionClient(self, NavigateThroughPoses, 'navigate_through_poses')
        self.nav_to_pose_client = ActionClient(self, NavigateToPose, 'navigate_to_pose')
        self.follow_waypoints_client = ActionClient(self, FollowWaypoints, 'follow_waypoints')
        self.follow_gps_waypoints_client = ActionClient(self, FollowGPSWaypoints, 'follow_gps_waypoints')
        self.follow_path_client = ActionClient(self, FollowPath, 'follow_path')
        self.compute_path_to_pose_client = ActionClient(self, ComputePathToPose, 'compute_path_to_pose')
        self.compute_path_through_poses_client = ActionClient(self, ComputePathThroughPoses, 'compute_path_through_poses')
        self.smoother_client = ActionClient(self, SmoothPath, 'smooth_path')
        self.spin_client = ActionClient(self, Spin, 'spin')
        self.backup_client = ActionClient(self, BackUp, 'backup')
        self.drive_on_heading_client = ActionClient(self, DriveOnHeading, 'drive_on_heading')
        self.assisted_teleop_client = ActionClient(self, AssistedTeleop, 'assisted_teleop')
        self.docking_client = ActionClient(self, DockRobot, 'dock_robot')
        self.undocking_client = ActionClient(self, UndockRobot, 'undock_robot')
        self.localization_pose_sub = self.create_subscription(
            PoseWithCovarianceStamped, 'amcl_pose', self._amclPoseCallback, amcl_pose_qos)
        self.initial_pose_pub = self.create_publisher(PoseWithCovarianceStamped, 'initialpose', 10)
        self.change_maps_srv = self.create_client(LoadMap, 'map_server/load_map')
        self.clear_costmap_global_srv = self.create_client(
            ClearEntireCostmap, 'global_costmap/clear_entirely_global_costmap')
        self.clear_costmap_local_srv = self.create_client(
            ClearEntireCostmap, 'local_costmap/clear_entirely_local_costmap')
        self.clear_costmap_except_region_srv = self.create_client(
            ClearCostmapExceptRegion, 'local_costmap/clear_costmap_except_region')
        self.clear_costmap_around_robot_srv = self.create_client(
            ClearCostmapAroundRobot, 'local_costmap/clear_costmap_around_robot')
        self.clear_costmap_around_pose_srv = self.create_client(
            ClearCostmapAroundPose, 'local_costmap/clear_costmap_around_pose')
        self.get_costmap_global_srv = self.create_client(GetCostmap, 'global_costmap/get_costmap')
        self.get_costmap_local_srv = self.create_client(GetCostmap, 'local_costmap/get_costmap')

    def destroyNode(self) -> None:
        """Nav2's spelling of `destroy_node`."""
        self.destroy_node()

    def destroy_node(self) -> None:
        """Destroy the navigator's action clients, then the node."""
        for client in (self.nav_through_poses_client, self.nav_to_pose_client, self.follow_waypoints_client,
                       self.follow_gps_waypoints_client,
                       self.follow_path_client, self.compute_path_to_pose_client,
                       self.compute_path_through_poses_client, self.spin_client, self.backup_client,
                       self.drive_on_heading_client, self.assisted_teleop_client, self.docking_client,
                       self.undocking_client):
            client.destroy()
        super().destroy_node()

    # -- localization --------------------------------------------------------------------------
    def setInitialPose(self, initial_pose: Any) -> None:
        """Store the pose and publish it once on `initialpose` (waitUntilNav2Active repeats it
        until amcl answers)."""
        self.initial_pose_received = False
        self.initial_pose = initial_pose
        self._setInitialPose()

    def _setInitialPose(self) -> None:
        msg = PoseWithCovarianceStamped()
        msg.pose.pose = self.initial_pose.pose
        msg.header.frame_id = self.initial_pose.header.frame_id
        msg.header.stamp = self.initial_pose.header.stamp
        self.info('Publishing Initial Pose')
        self.initial_pose_pub.publish(msg)

    def _amclPoseCallback(self, msg: Any) -> None:
        self.debug('Received amcl pose')
        self.initial_pose_received = True

    # -- tasks ---------------------------------------------------------------------------------
    def _send(self, client: Any, goal: Any, what: str, feedback: bool = True) -> bool:
        self.debug(f"Waiting for '{what}' action server")
        while not client.wait_for_server(timeout_sec=1.0):
            self.info(f"'{what}' action server not available, waiting...")
        send_goal_future = client.send_goal_async(goal, self._feedbackCallback if feedback else None)
        zros.spin_until_future_complete(self, send_goal_future)
        self.goal_handle = send_goal_future.result()
        if self.goal_handle is None or not self.goal_handle.accepted:
            self.error(f'{what} request was rejected!')
            return False
        self.result_future = self.goal_handle.get_result_async()
        return True

    def goThroughPoses(self, poses: list, behavior_tree: str = '') -> bool:
        """Send a NavigateThroughPoses goal: reach each pose in turn without stopping at them.

        Waits (logging once a second) until bt_navigator's action server is up.

        :param poses: geometry_msgs/msg/PoseStamped goals, in order.
        :param behavior_tree: A behavior tree XML file; empty for the navigator's default.
        :return: ``True`` if the goal was accepted; then poll `isTaskComplete()`.
        """
        self.info(f'Navigating with {len(poses)} goals....')
        return self._send(self.nav_through_poses_client,
                          NavigateThroughPoses.Goal(poses=list(poses), behavior_tree=behavior_tree),
                          'NavigateThroughPoses')

    def goToPose(self, pose: Any, behavior_tree: str = '') -> bool:
        """Send a NavigateToPose goal.

        Waits (logging once a second) until bt_navigator's action server is up.

        :param pose: The goal, a geometry_msgs/msg/PoseStamped (usually in the ``map`` frame).
        :param behavior_tree: A behavior tree XML file; empty for the navigator's default.
        :return: ``True`` if the goal was accepted; then poll `isTaskComplete()`.
        """
        self.info(f'Navigating to goal: {pose.pose.position.x} {pose.pose.position.y}...')
        return self._send(self.nav_to_pose_client, NavigateToPose.Goal(pose=pose, behavior_tree=behavior_tree),
                          'NavigateToPose')

    def followWaypoints(self, poses: list) -> bool:
        """Send a FollowWaypoints goal: stop at each pose in turn (the waypoint follower's task).

        :param poses: geometry_msgs/msg/PoseStamped waypoints, in order.
        :return: ``True`` if the goal was accepted; then poll `isTaskComplete()`.
        """
        self.info(f'Following {len(poses)} goals....')
        return self._send(self.follow_waypoints_client, FollowWaypoints.Goal(poses=list(poses)), 'FollowWaypoints')

    def followGpsWaypoints(self, gps_poses: list) -> bool:
        """Send a FollowGPSWaypoints goal (Nav2 Jazzy): the waypoint follower converts each pose
        with robot_localization's /fromLL service, then stops at each in turn.

        :param gps_poses: geographic_msgs/msg/GeoPose waypoints, in order.
        :return: ``True`` if the goal was accepted; then poll `isTaskComplete()`.
        """
        self.info(f'Following {len(gps_poses)} gps goals....')
        return self._send(self.follow_gps_waypoints_client, FollowGPSWaypoints.Goal(gps_poses=list(gps_poses)),
                          'FollowGPSWaypoints')

    def spin(self, spin_dist: float = 1.57, time_allowance: int = 10) -> bool:
        """Ask the behavior server to turn the robot in place.

        :param spin_dist: The angle to turn [rad], counter-clockwise positive.
        :param time_allowance: Seconds the behavior may take.
        :return: ``True`` if the goal was accepted.
        """
        goal = Spin.Goal(target_yaw=float(spin_dist))
        goal.time_allowance.sec = int(time_allowance)
        self.info(f'Spinning to angle {goal.target_yaw}....')
        return self._send(self.spin_client, goal, 'Spin')

    def backup(self, backup_dist: float = 0.15, backup_speed: float = 0.025, time_allowance: int = 10) -> bool:
        """Ask the behavior server to drive the robot straight backwards.

        :param backup_dist: The distance to cover [m].
        :param backup_speed: The speed [m/s].
        :param time_allowance: Seconds the behavior may take.
        :return: ``True`` if the goal was accepted.
        """
        goal = BackUp.Goal(speed=float(backup_speed))
        goal.target.x = float(backup_dist)
        goal.time_allowance.sec = int(time_allowance)
        self.info(f'Backing up {goal.target.x} m at {goal.speed} m/s....')
        return self._send(self.backup_client, goal, 'BackUp')

    def driveOnHeading(self, dist: float = 0.15, speed: float = 0.025, time_allowance: int = 10) -> bool:
        """Ask the behavior server to drive the robot straight along its current heading.

        :param dist: The distance to cover [m].
        :param speed: The speed [m/s].
        :param time_allowance: Seconds the behavior may take.
        :return: ``True`` if the goal was accepted.
        """
        goal = DriveOnHeading.Goal(speed=float(speed))
        goal.target.x = float(dist)
        goal.time_allowance.sec = int(time_allowance)
        self.info(f'Driving on heading {goal.target.x} m at {goal.speed} m/s....')
        return self._send(self.drive_on_heading_client, goal, 'DriveOnHeading')

    def assistedTeleop(self, time_allowance: int = 30) -> bool:
        """Start the behavior server's assisted teleop: `cmd_vel_teleop` is passed on to the
        robot, slowed before obstacles, until a message on `preempt_teleop` or `time_allowance`
        seconds (0: no limit).

        :param time_allowance: seconds the task may run.
        :return: whether the behaviour accepted the task.
        """
        goal = AssistedTeleop.Goal()
        goal.time_allowance.sec = int(time_allowance)
        self.info("Running 'assisted_teleop'....")
        return self._send(self.assisted_teleop_client, goal, 'AssistedTeleop')

    def dockRobotByPose(self, dock_pose: Any, dock_type: str = '', nav_to_dock: bool = True) -> bool:
        """Dock at a pose (Nav2 Jazzy): the docking server reaches the dock's staging pose, through
        the navigator if `nav_to_dock`, then drives onto the dock.

        :param dock_pose: The dock's geometry_msgs/msg/PoseStamped.
        :param dock_type: One of the server's `dock_plugins`; empty if it has only one.
        :param nav_to_dock: Navigate to the staging pose first (else the robot must be near it).
        :return: ``True`` if the goal was accepted; then poll `isTaskComplete()`.
        """
        goal = DockRobot.Goal(use_dock_id=False, dock_pose=dock_pose, dock_type=dock_type,
                              navigate_to_staging_pose=nav_to_dock)
        p = dock_pose.pose.position
        self.info(f'Docking at pose: ({p.x}, {p.y}) in {dock_pose.header.frame_id}...')
        return self._send(self.docking_client, goal, 'DockRobot')

    def dockRobotByID(self, dock_id: str, nav_to_dock: bool = True) -> bool:
        """Dock at a dock of the docking server's database (Nav2 Jazzy).

        :param dock_id: The dock's name in the `docks` parameter or the dock database file.
        :param nav_to_dock: Navigate to the staging pose first (else the robot must be near it).
        :return: ``True`` if the goal was accepted; then poll `isTaskComplete()`.
        """
        self.info(f'Docking at dock ID: {dock_id}...')
        return self._send(self.docking_client,
                          DockRobot.Goal(use_dock_id=True, dock_id=dock_id, navigate_to_staging_pose=nav_to_dock),
                          'DockRobot')

    def undockRobot(self, dock_type: str = '') -> bool:
        """Back off the dock to its staging pose (Nav2 Jazzy).

        :param dock_type: The dock's type; empty if the server docked the robot itself or has one type.
        :return: ``True`` if the goal was accepted; then poll `isTaskComplete()`.
        """
        self.info(f'Undocking from dock of type: {dock_type}...')
        return self._send(self.undocking_client, UndockRobot.Goal(dock_type=dock_type), 'UndockRobot')

    def followPath(self, path: Any, controller_id: str = '', goal_checker_id: str = '') -> bool:
        """Have the controller server follow a path already planned (from `getPath`, say).

        :param path: A nav_msgs/msg/Path.
        :param controller_id: The controller plugin to use; empty for the only or default one.
        :param goal_checker_id: The goal checker plugin to use; empty for the default.
        :return: ``True`` if the goal was accepted.
        """
        self.info('Executing path...')
        return self._send(self.follow_path_client,
                          FollowPath.Goal(path=path, controller_id=controller_id, goal_checker_id=goal_checker_id),
                          'FollowPath')

    def cancelTask(self) -> None:
        """Cancel the running task, if any, and wait for the server's answer."""
        self.info('Canceling current task.')
        if self.result_future and self.goal_handle is not None:
            future = self.goal_handle.cancel_goal_async()
            zros.spin_until_future_complete(self, future)

    def isTaskComplete(self) -> bool:
        """Spin 0.1 s on the result; True once the task has ended (or none was started)."""
        if not self.result_future:
            return True
        zros.spin_until_future_complete(self, self.result_future, timeout_sec=0.10)
        if self.result_future.result():
            self.status = self.result_future.result().status
            if self.status != GoalStatus.STATUS_SUCCEEDED:
                self.debug(f'Task with failed with status code: {self.status}')
            return True
        return False

    def getFeedback(self) -> Any:
        """The latest feedback of the running task.

        :return: The action's Feedback message (e.g. NavigateToPose's, with
            `distance_remaining`), or ``None`` before any arrived.
        """
        return self.feedback

    def getResult(self) -> TaskResult:
        """How the last finished task ended; call it once `isTaskComplete()` is ``True``.

        :return: SUCCEEDED, CANCELED, FAILED (aborted) or UNKNOWN.
        """
        if self.status == GoalStatus.STATUS_SUCCEEDED:
            return TaskResult.SUCCEEDED
        if self.status == GoalStatus.STATUS_ABORTED:
            return TaskResult.FAILED
        if self.status == GoalStatus.STATUS_CANCELED:
            return TaskResult.CANCELED
        return TaskResult.UNKNOWN

    def _feedbackCallback(self, msg: Any) -> None:
        self.debug('Received action feedback message')
        self.feedback = msg.feedback

    # -- waiting for Nav2 ----------------------------------------------------------------------
    def waitUntilNav2Active(self, navigator: str = 'bt_navigator', localizer: str = 'amcl',
                            timeout: float | None = None) -> bool:
        """Block until the localizer (if any) and the navigator are active, and amcl has a pose.

        Every few seconds it says who is not ready and why. With `timeout` [s] it gives up and
        returns False; otherwise it returns True once Nav2 is ready. `localizer='robot_localization'`
        (Nav2 Jazzy's name for a localizer that is not a lifecycle node, as with GPS) or ''
        waits for the navigator alone.
        """
        deadline = None if timeout is None else time.monotonic() + timeout
        if localizer and localizer != 'robot_localization':      # not a lifecycle node: nothing to ask
            if not self._waitForNodeToActivate(localizer, deadline):
                return False
            if localizer == 'amcl' and not self._waitForInitialPose(deadline):
                return False
        if not self._waitForNodeToActivate(navigator, deadline):
            return False
        self.info('Nav2 is ready for use!')
        return True

    def _waitForNodeToActivate(self, node_name: str, deadline: float | None = None) -> bool:
        self.debug(f'Waiting for {node_name} to become active..')
        client = self.create_client(GetState, f'{node_name}/get_state')
        last_report = 0.0
        try:
            while True:
                reason = self._not_active_reason(client, node_name)
                if reason is None:
                    return True
                now = time.monotonic()
                if deadline is not None and now > deadline:
                    self.error(f'Gave up waiting for Nav2: {reason}')
                    return False
                if now - last_report >= _REPORT_PERIOD_S:
                    self.info(f'Waiting for Nav2: {reason}')
                    last_report = now
                zros.spin_once(self, timeout_sec=0.5)
        finally:
            self.destroy_client(client)

    def _not_active_reason(self, client: Any, node_name: str) -> str | None:
        if not client.wait_for_service(timeout_sec=0.5):
            reason = f'{node_name} is not running (no {node_name}/get_state service)'
            if node_name == 'amcl':
                reason += "; with SLAM there is no amcl: call waitUntilNav2Active(localizer='slam_toolbox') or localizer=''"
            return reason
        future = client.call_async(GetState.Request())
        zros.spin_until_future_complete(self, future, timeout_sec=2.0)
        if not future.done() or future.result() is None:
            return f'{node_name} does not answer on {node_name}/get_state'
        label = future.result().current_state.label
        if label == 'active':
            return None
        return (f'{node_name} is {label}, not active (its lifecycle manager brings it up: is the '
                'navigation or localization launch file running with autostart?)')

    def _waitForInitialPose(self, deadline: float | None = None) -> bool:
        last_report = 0.0
        while not self.initial_pose_received:
            now = time.monotonic()
            if deadline is not None and now > deadline:
                self.error('Gave up waiting for Nav2: amcl has no initial pose')
                return False
            if self.initial_pose is not None:
                self._setInitialPose()
            if now - last_report >= _REPORT_PERIOD_S:
                self.info('Waiting for Nav2: amcl has no initial pose'
                          + ('' if self.initial_pose is not None else
                             ' (call setInitialPose(), or give one with RViz\'s 2D Pose Estimate)'))
                last_report = now
            zros.spin_once(self, timeout_sec=1.0)
        return True

    # -- planning ------------------------------------------------------------------------------
    def _path(self, client: Any, goal: Any, what: str) -> Any:
        if not self._send(client, goal, what, feedback=False):
            return None
        zros.spin_until_future_complete(self, self.result_future)
        self.status = self.result_future.result().status
        if self.status != GoalStatus.STATUS_SUCCEEDED:
            failure = self.result_future.result().result
            self.warn(f'Getting path failed with status code: {self.status}, '
                      f'error code: {failure.error_code}, error msg: {failure.error_msg}')
            return None
        return self.result_future.result().result.path

    def getPath(self, start: Any, goal: Any, planner_id: str = '', use_start: bool = False) -> Any:
        """Ask the planner server for a path from `start` to `goal`, without driving it.

        :param start: A geometry_msgs/msg/PoseStamped; used only with `use_start`.
        :param goal: A geometry_msgs/msg/PoseStamped.
        :param planner_id: The planner plugin; empty for the default.
        :param use_start: Plan from `start` instead of the robot's current pose.
        :return: A nav_msgs/msg/Path, or ``None`` if planning failed (the reason is logged).
        """
        return self._path(self.compute_path_to_pose_client,
                          ComputePathToPose.Goal(start=start, goal=goal, planner_id=planner_id, use_start=use_start),
                          'ComputePathToPose')

    def getPathThroughPoses(self, start: Any, goals: list, planner_id: str = '', use_start: bool = False) -> Any:
        """Ask the planner server for one path through several goals, without driving it.

        :param start: A geometry_msgs/msg/PoseStamped; used only with `use_start`.
        :param goals: geometry_msgs/msg/PoseStamped goals, in order.
        :param planner_id: The planner plugin; empty for the default.
        :param use_start: Plan from `start` instead of the robot's current pose.
        :return: A nav_msgs/msg/Path, or ``None`` if planning failed (the reason is logged).
        """
        return self._path(self.compute_path_through_poses_client,
                          ComputePathThroughPoses.Goal(start=start, goals=list(goals), planner_id=planner_id,
                                                       use_start=use_start),
                          'ComputePathThroughPoses')

    def smoothPath(self, path: Any, smoother_id: str = '', max_duration: float = 2.0,
                   check_for_collision: bool = False) -> Any:
        """The smoother_server's smoothing of nav_msgs/Path `path` (None if it failed)."""
        self.info('Smoothing path...')
        return self._path(self.smoother_client,
                          SmoothPath.Goal(path=path, smoother_id=smoother_id,
                                          max_smoothing_duration=Duration(seconds=max_duration).to_msg(),
                                          check_for_collisions=check_for_collision),
                          'SmoothPath')

    # -- maps and costmaps ---------------------------------------------------------------------
    def _call(self, client: Any, request: Any, what: str) -> Any:
        while not client.wait_for_service(timeout_sec=1.0):
            self.info(f'{what} service not available, waiting...')
        future = client.call_async(request)
        zros.spin_until_future_complete(self, future)
        return future.result()

    def changeMap(self, map_filepath: str) -> bool:
        """Have the map server load another map (and publish it on /map).

        :param map_filepath: The map's YAML file.
        :return: ``True`` if the map server loaded it.
        """
        response = self._call(self.change_maps_srv, LoadMap.Request(map_url=map_filepath), 'Change map')
        if response is None or response.result != LoadMap.Response.RESULT_SUCCESS:
            self.error('Change map request failed!')
            return False
        self.info('Change map request was successful!')
        return True

    def clearAllCostmaps(self) -> None:
        """Clear both costmaps of every obstacle (local first, then global)."""
        self.clearLocalCostmap()
        self.clearGlobalCostmap()

    def clearLocalCostmap(self) -> None:
        """Clear the local costmap of every obstacle; sensors fill it again."""
        self._call(self.clear_costmap_local_srv, ClearEntireCostmap.Request(), 'Clear local costmaps')

    def clearGlobalCostmap(self) -> None:
        """Clear the global costmap's obstacle layers; the static map stays."""
        self._call(self.clear_costmap_global_srv, ClearEntireCostmap.Request(), 'Clear global costmaps')

    def clearCostmapExceptRegion(self, reset_distance: float) -> None:
        """Forget the local costmap's obstacles outside the square of side `reset_distance` [m]
        around the robot (Nav2 Jazzy)."""
        self._call(self.clear_costmap_except_region_srv,
                   ClearCostmapExceptRegion.Request(reset_distance=float(reset_distance)), 'ClearCostmapExceptRegion')

    def clearCostmapAroundRobot(self, reset_distance: float) -> None:
        """Forget the local costmap's obstacles in the square of side `reset_distance` [m]
        around the robot (Nav2 Jazzy)."""
        self._call(self.clear_costmap_around_robot_srv,
                   ClearCostmapAroundRobot.Request(reset_distance=float(reset_distance)), 'ClearCostmapAroundRobot')

    def clearCostmapAroundPose(self, pose: Any, reset_distance: float) -> None:
        """Forget the local costmap's obstacles in the square of side `reset_distance` [m]
        around `pose` (a PoseStamped; Nav2 Jazzy)."""
        self._call(self.clear_costmap_around_pose_srv,
                   ClearCostmapAroundPose.Request(pose=pose, reset_distance=float(reset_distance)),
                   'ClearCostmapAroundPose')

    def getGlobalCostmap(self) -> Any:
        """Fetch the global costmap.

        :return: A nav2_msgs/msg/Costmap.
        """
        return self._call(self.get_costmap_global_srv, GetCostmap.Request(), 'Get global costmaps').map

    def getLocalCostmap(self) -> Any:
        """Fetch the local costmap.

        :return: A nav2_msgs/msg/Costmap.
        """
        return self._call(self.get_costmap_local_srv, GetCostmap.Request(), 'Get local costmaps').map

    # -- lifecycle -----------------------------------------------------------------------------
    def _manage(self, command: int, verb: str) -> None:
        self.info(f'{verb} up lifecycle nodes based on lifecycle_manager.' if verb == 'Starting'
                  else f'{verb} down lifecycle nodes based on lifecycle_manager.')
        for name, types in self.get_service_names_and_types():
            if 'nav2_msgs/srv/ManageLifecycleNodes' in types:
                self.info(f'{verb} {name}')
                self._call(self.create_client(ManageLifecycleNodes, name),
                           ManageLifecycleNodes.Request(command=command), name)
        self.info(f'Nav2 is {"ready for use" if verb == "Starting" else "shut down"}!')

    def lifecycleStartup(self) -> None:
        """Ask every lifecycle manager to configure and activate its nodes."""
        self._manage(ManageLifecycleNodes.Request.STARTUP, 'Starting')

    def lifecycleShutdown(self) -> None:
        """Ask every lifecycle manager to shut its nodes down."""
        self._manage(ManageLifecycleNodes.Request.SHUTDOWN, 'Shutting')

    # -- logging -------------------------------------------------------------------------------
    def info(self, msg: str) -> None:
        """Log `msg` at INFO through the node's logger (and /rosout)."""
        self.get_logger().info(msg)

    def warn(self, msg: str) -> None:
        """Log `msg` at WARN through the node's logger (and /rosout)."""
        self.get_logger().warn(msg)

    def error(self, msg: str) -> None:
        """Log `msg` at ERROR through the node's logger (and /rosout)."""
        self.get_logger().error(msg)

    def debug(self, msg: str) -> None:
        """Log `msg` at DEBUG through the node's logger (and /rosout)."""
        self.get_logger().debug(msg)
