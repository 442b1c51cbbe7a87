"""opennav_docking's docking server (Nav2 Jazzy; node name `docking_server`): docks and undocks.

    zros run opennav_docking opennav_docking --ros-args -r __node:=docking_server --params-file nav2_params.yaml

A lifecycle node with the `dock_robot` (nav2_msgs/DockRobot) and `undock_robot` actions.
Docks come from the `docks` parameter list (`<dock>.type`, `.frame`, `.pose` [x, y, yaw], `.id`)
or a `dock_database` YAML file; dock types are the `dock_plugins`, each served with
simple_charging_dock's behaviour (`opennav_docking::SimpleNonChargingDock` is a dock that never
charges). Docking: navigate to the dock's staging pose through bt_navigator's
`navigate_to_pose` (unless the robot is already within `dock_prestaging_tolerance` of it or the
goal says not to), then drive onto the dock with the graceful control law of
zros.navigation.docking until the robot is within `docking_threshold` of the dock pose, then
wait for charging. Undocking backs off to the staging pose.

What differs from Nav2: no dock detection. zros's simulator has no dock model or AprilTag, so
the "detected" dock pose is the known one from the database or the goal
(`use_external_detection_pose` and `external_detection_*` are read and ignored); stall detection
and the controller's collision checking are not implemented. Charging follows Nav2's plugin
parameters: with `use_battery_status` the robot charges when `battery_state`'s current exceeds
`charging_threshold`, otherwise being docked counts as charging.
"""
from __future__ import annotations

import math
import sys
import time
from typing import Any

import zros
from zros.action import ActionClient
from zros.executors import ExternalShutdownException, spin_nodes
from zros.lifecycle import LifecycleNode, State, TransitionCallbackReturn
from zros.navigation.docking import (ControlLaw, Dock, DockDatabaseError, approach_target, is_within,
                                     load_dock_database, parse_docks, staging_pose, to_robot_frame)
from zros.navigation.node_support import Nav2Params, duration_msg, lookup_pose, pose_in_frame, quaternion_of
from zros.navigation.servers import GoalCall, GoalRunner, gated_action_server, RESULT_TIMEOUT_S
from zros.tf2_ros import Buffer, TransformException, TransformListener

from interfaces.action_msgs.msg import GoalStatus
from interfaces.geometry_msgs.msg import PoseStamped, Twist
from interfaces.nav2_msgs.action import DockRobot, NavigateToPose, UndockRobot
from interfaces.nav2_msgs.srv import ReloadDockDatabase
from interfaces.sensor_msgs.msg import BatteryState

_CHARGING = 'opennav_docking::SimpleChargingDock'
_NON_CHARGING = 'opennav_docking::SimpleNonChargingDock'


class DockPlugin:
    """One `dock_plugins` entry: simple_charging_dock's parameters and its docked/charging tests."""

    def __init__(self, node: Any, prm: Nav2Params, name: str) -> None:
        self.name = name
        plugin = prm.get(f'{name}.plugin', _CHARGING).replace('/', '::')
        if plugin not in (_CHARGING, _NON_CHARGING):
            node.get_logger().info(f'{name}: {plugin} is not implemented in zros; served as SimpleChargingDock')
        self.is_charger = plugin != _NON_CHARGING
        self.docking_threshold = prm.get(f'{name}.docking_threshold', 0.05)
        self.staging_x_offset = prm.get(f'{name}.staging_x_offset', -0.7)
        self.staging_yaw_offset = prm.get(f'{name}.staging_yaw_offset', 0.0)
        self.use_battery_status = self.is_charger and prm.get(f'{name}.use_battery_status', True)
        self.charging_threshold = prm.get(f'{name}.charging_threshold', 0.5)
        for unused, default in (('use_external_detection_pose', False), ('external_detection_timeout', 1.0),
                                ('external_detection_translation_x', -0.20),
                                ('external_detection_translation_y', 0.0),
                                ('external_detection_rotation_roll', -1.57),
                                ('external_detection_rotation_pitch', 1.57),
                                ('external_detection_rotation_yaw', 0.0), ('filter_coef', 0.1),
                                ('use_stall_detection', False), ('stall_velocity_threshold', 1.0),
                                ('stall_effort_threshold', 1.0)):
            prm.get(f'{name}.{unused}', default)
        self.current: float | None = None
        if self.use_battery_status:
            node.create_subscription(BatteryState, 'battery_state', self._on_battery, 1)

    def _on_battery(self, msg: Any) -> None:
        self.current = float(msg.current)

    def staging(self, dock: tuple[float, float, float]) -> tuple[float, float, float]:
        return staging_pose(dock, self.staging_x_offset, self.staging_yaw_offset)

    def is_docked(self, robot: tuple, dock: tuple | None) -> bool:
        """The robot's base within `docking_threshold` of the (known) dock pose, same frame."""
        return dock is not None and is_within(robot, dock, self.docking_threshold)

    def is_charging(self, robot: tuple, dock: tuple | None) -> bool:
        if not self.is_charger:
            return False
        if self.use_battery_status:
            return self.current is not None and self.current > self.charging_threshold
        return self.is_docked(robot, dock)


class DockingServer(LifecycleNode):
    def __init__(self) -> None:
        super().__init__('docking_server')
        prm = Nav2Params(self)
        self.frequency = prm.get('controller_frequency', 50.0)
        self.initial_perception_timeout = prm.get('initial_perception_timeout', 5.0)
        self.wait_charge_timeout = prm.get('wait_charge_timeout', 5.0)
        self.dock_approach_timeout = prm.get('dock_approach_timeout', 30.0)
        self.undock_linear_tolerance = prm.get('undock_linear_tolerance', 0.05)
        self.undock_angular_tolerance = prm.get('undock_angular_tolerance', 0.05)
        self.max_retries = prm.get('max_retries', 3)
        self.base_frame = prm.get('base_frame', 'base_link')
        self.fixed_frame = prm.get('fixed_frame', 'odom')
        self.dock_backwards = prm.get('dock_backwards', False)
        self.prestaging_tolerance = prm.get('dock_prestaging_tolerance', 0.5)
        self.navigator_bt_xml = prm.get('navigator_bt_xml', '')
        result_timeout = prm.get('action_server_result_timeout', RESULT_TIMEOUT_S)
        self.law = ControlLaw.from_params(prm.get)
        for unused, default in (('use_collision_detection', True), ('costmap_topic', 'local_costmap/costmap_raw'),
                                ('footprint_topic', 'local_costmap/published_footprint'),
                                ('transform_tolerance', 0.1), ('projection_time', 5.0),
                                ('simulation_time_step', 0.1), ('dock_collision_threshold', 0.3),
                                ('rotate_to_heading_angular_vel', 1.0),
                                ('rotate_to_heading_max_angular_accel', 3.2)):
            prm.get(f'controller.{unused}', default)
        self.plugin_names = prm.get('dock_plugins', [])
        self.plugins = {name: DockPlugin(self, prm, name) for name in self.plugin_names}
        self.database_path = prm.get('dock_database', '')
        self.dock_names = prm.get('docks', [])
        self.dock_entries = {name: {'type': prm.get(f'{name}.type', ''), 'frame': prm.get(f'{name}.frame', 'map'),
                                    'pose': prm.get(f'{name}.pose', []), 'id': prm.get(f'{name}.id', '')}
                             for name in self.dock_names}
        prm.report_unused()
        self.docks: dict[str, Dock] = {}
        self.current_type = ''             # the dock type of the last successful docking
        self.docked_at: tuple | None = None  # that dock's pose in the fixed frame
        self.tf_buffer = Buffer(node=self)
        self.tf_listener = TransformListener(self.tf_buffer, self)
        self.cmd_pub = self.create_lifecycle_publisher(Twist, 'cmd_vel', 1)
        self.navigator = ActionClient(self, NavigateToPose, 'navigate_to_pose')
        self.goals = GoalRunner(self, stop=lambda: self.cmd_pub.publish(Twist()))
        gated_action_server(self, DockRobot, 'dock_robot', self._dock, result_timeout=result_timeout)
        gated_action_server(self, UndockRobot, 'undock_robot', self._undock, result_timeout=result_timeout)
        self.create_service(ReloadDockDatabase, '~/reload_database', self._reload)

    def on_configure(self, state: State) -> TransitionCallbackReturn:
        self.get_logger().info(f'Configuring {self.get_name()}')
        if not self.plugins:
            self.get_logger().error('Charging dock plugins not given! (dock_plugins is empty)')
            return TransitionCallbackReturn.FAILURE
        try:
            self.docks = self._load_docks(self.database_path)
        except DockDatabaseError as exc:
            self.get_logger().error(str(exc))
            return TransitionCallbackReturn.FAILURE
        self.get_logger().info(f'Docking Server has {len(self.plugins)} dock types and {len(self.docks)} dock '
                               'instances available (dock detection: the known dock pose; zros has no perception)')
        return TransitionCallbackReturn.SUCCESS

    def _load_docks(self, path: str) -> dict[str, Dock]:
        docks = load_dock_database(path) if path else parse_docks(self.dock_entries, 'the docks parameters')
        for dock in docks.values():
            if dock.type not in self.plugins:
                raise DockDatabaseError(f'Dock {dock.name} has type {dock.type}, which is not in dock_plugins '
                                        f'({", ".join(self.plugin_names)})')
        return docks

    def _reload(self, request: Any, response: Any) -> Any:
        try:
            self.docks = self._load_docks(request.filepath)
            response.success = True
        except DockDatabaseError as exc:
            self.get_logger().error(str(exc))
            response.success = False
        return response

    # -- helpers -------------------------------------------------------------------------------
    def _plugin(self, dock_type: str) -> DockPlugin | None:
        if not dock_type and len(self.plugins) == 1:
            return next(iter(self.plugins.values()))
        return self.plugins.get(dock_type)

    def _robot(self, frame: str) -> tuple[float, float, float]:
        return lookup_pose(self.tf_buffer, frame, self.base_frame)

    def _in_fixed(self, pose: tuple[float, float, float], frame: str) -> tuple[float, float, float]:
        stamped = PoseStamped()
        stamped.header.frame_id = frame
        stamped.pose.position.x, stamped.pose.position.y = pose[0], pose[1]
        quaternion_of(pose[2], stamped.pose.orientation)
        return pose_in_frame(self.tf_buffer, stamped, self.fixed_frame)

    def _drive(self, target_in_fixed: tuple, backward: bool) -> None:
        v, w = self.law.velocity(to_robot_frame(self._robot(self.fixed_frame), target_in_fixed), backward)
        cmd = Twist()
        cmd.linear.x, cmd.angular.z = v, w
        self.cmd_pub.publish(cmd)

    def _staging_goal(self, staging: tuple, frame: str) -> Any:
        goal = NavigateToPose.Goal(behavior_tree=self.navigator_bt_xml)
        goal.pose.header.frame_id = frame
        goal.pose.header.stamp = self.get_clock().now().to_msg()
        goal.pose.pose.position.x, goal.pose.pose.position.y = staging[0], staging[1]
        quaternion_of(staging[2], goal.pose.pose.orientation)
        return goal

    # -- docking -------------------------------------------------------------------------------
    def _dock(self, handle: Any) -> Any:
        goal = handle.request
        result = DockRobot.Result(success=False)
        self.goals.slot.take(handle)
        started = time.monotonic()
        if goal.use_dock_id:
            self.get_logger().info(f'Attempting to dock robot at {goal.dock_id}.')
            dock = self.docks.get(goal.dock_id)
            if dock is None:
                return self._end(handle, result, DockRobot.Result.DOCK_NOT_IN_DB,
                                 f'Dock ID requested, {goal.dock_id}, is not in the dock database')
        else:
            p = goal.dock_pose.pose
            self.get_logger().info(f'Attempting to dock robot at position ({p.position.x:.2f}, {p.position.y:.2f}).')
            if self._plugin(goal.dock_type) is None:
                return self._end(handle, result, DockRobot.Result.DOCK_NOT_VALID,
                                 f"Dock type '{goal.dock_type}' has no valid plugin!")
            x, y, yaw = pose_in_frame(self.tf_buffer, goal.dock_pose, goal.dock_pose.header.frame_id or 'map')
            dock = Dock('', goal.dock_type, goal.dock_pose.header.frame_id or 'map', (x, y, yaw))
        plugin = self._plugin(dock.type)
        if plugin is None:
            return self._end(handle, result, DockRobot.Result.DOCK_NOT_VALID,
                             f"Dock type '{dock.type}' has no valid plugin!")
        try:
            dock_fixed = self._in_fixed(dock.pose, dock.frame)
            robot = self._robot(self.fixed_frame)
        except TransformException as exc:
            return self._end(handle, result, DockRobot.Result.UNKNOWN, f'Transform error: {exc}')
        if plugin.is_charger and (plugin.is_docked(robot, dock_fixed) or plugin.is_charging(robot, dock_fixed)):
            self.get_logger().info('Robot is already docked and/or charging (if applicable), no need to dock')
            result.success = True
            self._docked(plugin, dock_fixed)
            handle.succeed()
            self.goals.slot.release(handle)
            return result
        run = _Docking(self, handle, result, plugin, dock, dock_fixed, started)
        return self.goals.loop(handle, result, self.frequency, run.step, on_interrupt=run.interrupt)

    def _docked(self, plugin: DockPlugin, dock_fixed: tuple) -> None:
        self.current_type, self.docked_at = plugin.name, dock_fixed

    def _end(self, handle: Any, result: Any, code: int, message: str) -> Any:
        self.get_logger().error(message)
        result.error_code, result.error_msg, result.success = code, message, False
        self.goals.stop_if_current(handle)
        handle.abort()
        self.goals.slot.release(handle)
        return result

    # -- undocking -----------------------------------------------------------------------------
    def _undock(self, handle: Any) -> Any:
        goal = handle.request
        result = UndockRobot.Result(success=False)
        self.goals.slot.take(handle)
        plugin = self._plugin(goal.dock_type or self.current_type)
        if plugin is None:
            return self._end(handle, result, UndockRobot.Result.DOCK_NOT_VALID, 'No dock information to undock from!')
        self.get_logger().info(f'Attempting to undock robot of dock type {plugin.name}.')
        try:
            robot = self._robot(self.fixed_frame)
        except TransformException as exc:
            return self._end(handle, result, UndockRobot.Result.UNKNOWN, f'Transform error: {exc}')
        if plugin.is_charger and not plugin.is_docked(robot, self.docked_at) \
                and not plugin.is_charging(robot, self.docked_at):
            return self._end(handle, result, UndockRobot.Result.NONE, 'Robot is not in the dock, no need to undock')
        dock = (robot[0], robot[1], robot[2] + (math.pi if self.dock_backwards else 0.0))
        staging = plugin.staging(dock)
        deadline = time.monotonic() + goal.max_undocking_time
        backward = not self.dock_backwards

        def step() -> Any:
            if time.monotonic() > deadline:
                return self._end(handle, result, UndockRobot.Result.FAILED_TO_CONTROL, 'Undocking timed out')
            try:
                robot = self._robot(self.fixed_frame)
                if not is_within(robot, staging, self.undock_linear_tolerance, self.undock_angular_tolerance):
                    self._drive(staging, backward)
                    return None
            except TransformException as exc:
                return self._end(handle, result, UndockRobot.Result.UNKNOWN, f'Transform error: {exc}')
            self.get_logger().info('Robot has reached staging pose')
            self.cmd_pub.publish(Twist())
            if plugin.is_charger and plugin.is_charging(robot, self.docked_at):
                return self._end(handle, result, UndockRobot.Result.FAILED_TO_CONTROL, 'Failed to control off dock')
            self.get_logger().info('Robot has undocked!')
            self.current_type, self.docked_at = '', None
            result.success = True
            handle.succeed()
            return result
        return self.goals.loop(handle, result, self.frequency, step)


class _Docking:
    """One DockRobot goal as a state machine stepped by GoalRunner.loop: stage (navigate to the
    staging pose), perceive (the known pose), approach, wait for charge, and on a failed
    approach reset to the staging pose and retry (up to max_retries)."""

    def __init__(self, server: DockingServer, handle: Any, result: Any, plugin: DockPlugin, dock: Dock,
                 dock_fixed: tuple, started: float) -> None:
        self.s, self.handle, self.result, self.plugin = server, handle, result, plugin
        self.dock, self.dock_fixed, self.started = dock, dock_fixed, started
        self.staging = plugin.staging(dock.pose)                       # in the dock's frame
        self.staging_fixed = plugin.staging(dock_fixed)
        self.phase, self.phase_started = 'stage', time.monotonic()
        self.nav: GoalCall | None = None
        self.retries = 0

    def _feedback(self, state: int) -> None:
        fb = DockRobot.Feedback(state=state, num_retries=self.retries)
        fb.docking_time = duration_msg(time.monotonic() - self.started)
        self.handle.publish_feedback(fb)

    def _enter(self, phase: str) -> None:
        self.phase, self.phase_started = phase, time.monotonic()

    def _fail(self, code: int, message: str) -> Any:
        self.result.num_retries = self.retries
        return self.s._end(self.handle, self.result, code, message)

    def interrupt(self) -> None:
        if self.nav is not None:
            self.nav.cancel()
        self.s.cmd_pub.publish(Twist())

    def step(self) -> Any:
        try:
            return getattr(self, f'_{self.phase}')()
        except TransformException as exc:
            return self._fail(DockRobot.Result.UNKNOWN, f'Transform error: {exc}')

    def _stage(self) -> Any:
        self._feedback(DockRobot.Feedback.NAV_TO_STAGING_POSE)
        goal = self.handle.request
        if self.nav is None:
            robot = self.s._robot(self.dock.frame)
            if not goal.navigate_to_staging_pose or is_within(robot, self.staging, self.s.prestaging_tolerance):
                self.s.get_logger().info('Robot already within pre-staging pose tolerance for dock')
                self._enter('approach')
                return None
            self.nav = GoalCall(self.s.navigator, self.s._staging_goal(self.staging, self.dock.frame))
        if time.monotonic() - self.phase_started > goal.max_staging_time:
            self.nav.cancel()
            return self._fail(DockRobot.Result.FAILED_TO_STAGE, 'Navigation to the staging pose timed out')
        if not self.nav.poll():
            return None
        if self.nav.status != GoalStatus.STATUS_SUCCEEDED:
            return self._fail(DockRobot.Result.FAILED_TO_STAGE, 'Failed to navigate to the staging pose')
        self.s.get_logger().info('Successful navigation to staging pose')
        self._enter('approach')
        return None

    def _approach(self) -> Any:
        self._feedback(DockRobot.Feedback.CONTROLLING)
        robot = self.s._robot(self.s.fixed_frame)
        if self.plugin.is_docked(robot, self.dock_fixed) or self.plugin.is_charging(robot, self.dock_fixed):
            self.s.get_logger().info('Made contact with dock, waiting for charge to start (if applicable).')
            self.s.cmd_pub.publish(Twist())
            self._enter('charge')
            return self._charge()
        if time.monotonic() - self.phase_started > self.s.dock_approach_timeout:
            return self._retry(DockRobot.Result.FAILED_TO_CONTROL, 'Timed out approaching dock; dock nor charging (if applicable) detected')
        x, y, yaw = approach_target(self.dock_fixed)
        if self.s.dock_backwards:
            yaw += math.pi
        self.s._drive((x, y, yaw), self.s.dock_backwards)
        return None

    def _retry(self, code: int, message: str) -> Any:
        self.s.cmd_pub.publish(Twist())
        self.retries += 1
        if self.retries > self.s.max_retries:
            self.s.get_logger().error('Failed to dock, all retries have been used')
            return self._fail(code, message)
        self.s.get_logger().warn(f'Docking failed, will retry: {message}')
        self._enter('reset')
        return None

    def _reset(self) -> Any:
        self._feedback(DockRobot.Feedback.RETRY)
        robot = self.s._robot(self.s.fixed_frame)
        if is_within(robot, self.staging_fixed, self.s.undock_linear_tolerance, self.s.undock_angular_tolerance):
            self.s.get_logger().info('Returned to staging pose, attempting docking again')
            self._enter('approach')
            return None
        if time.monotonic() - self.phase_started > self.s.dock_approach_timeout:
            return self._fail(DockRobot.Result.FAILED_TO_CONTROL, 'Timed out resetting dock approach')
        self.s._drive(self.staging_fixed, not self.s.dock_backwards)
        return None

    def _charge(self) -> Any:
        robot = self.s._robot(self.s.fixed_frame)
        if self.plugin.is_charger and not self.plugin.is_charging(robot, self.dock_fixed):
            self._feedback(DockRobot.Feedback.WAIT_FOR_CHARGE)
            if time.monotonic() - self.phase_started > self.s.wait_charge_timeout:
                return self._retry(DockRobot.Result.FAILED_TO_CHARGE, 'Timed out waiting for charge to start')
            return None
        self.s.get_logger().info('Robot is charging!' if self.plugin.is_charger else 'Docking was successful!')
        self.s._docked(self.plugin, self.dock_fixed)
        self.result.success, self.result.num_retries = True, self.retries
        self.handle.succeed()
        return self.result


def main(args: list[str] | None = None) -> int:
    try:
        with zros.init(args=args):
            spin_nodes(DockingServer())
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    return 0


if __name__ == '__main__':
    sys.exit(main())
