"""gzserver: the simulated world in Gazebo's role, a 2D pymunk world with TurtleBot3s in it.

    zros run turtlebot3_gazebo gzserver --ros-args -p world:=turtlebot3_world -p x_pose:=-2.0
    zros launch turtlebot3_gazebo turtlebot3_world.launch.py          # the usual way

One node, `/gazebo`, runs zros.sim's Simulation on its own thread, in fixed 5 ms steps, paced
to `real_time_factor` x real time (0: as fast as it can), and publishes what Gazebo publishes:
`/clock` (rosgraph_msgs/Clock), and per robot what its model file's plugins say (a TurtleBot3:
`scan`, `odom`, `tf`, `joint_states`, `imu`; odometry in the world frame, Gazebo's default,
unless `odometry_source` says `encoder`), plus the ground truth apart under `sim/`
(`sim/ground_truth`, `sim/collisions`). The first robot also publishes its fixed frames and
wheels (`publish_robot_frames`) when no robot_state_publisher does. Commands come in on `cmd_vel`. Services: Gazebo's `/reset_simulation`,
`/reset_world`, `/pause_physics`, `/unpause_physics` (std_srvs/Empty), `/spawn_entity`,
`/delete_entity`, `/get_entity_state`, `/set_entity_state`, `/get_model_list` (gazebo_msgs),
Gazebo Sim's `/world/<world>/control` (ros_gz_interfaces/ControlWorld: pause, step N, reset),
and `/sim/get_map` (nav_msgs/GetMap: the world's exact occupancy, `map_resolution` m cells).

With `gz=True` it plays Gazebo Sim instead (ros_gz_sim's `gz sim`): `/clock`, the robots' topics
and the world's services (`/world/<world>/create`, `/remove`, `/control`) are on the hidden
Gazebo side (zros.sim.gz_topics), where only ros_gz_bridge makes ROS topics of them; a robot's
topics and frames are the ones its model's gz-sim plugins name, and Gazebo classic's ROS
services are not there.

Time: the simulation owns it. Steps never depend on when the thread wakes up, only on their
count, so a run at 20x and one at 1x with the same commands at the same simulated times give
the same trajectory; pacing only decides when steps happen on the wall clock. If the machine
cannot keep up, the simulation slows down (it never skips physics) and says so once.
"""
from __future__ import annotations

import math
import os
import sys
import threading
import time
from dataclasses import replace
from typing import Any

import zros
from zros.errors import CliError
from zros.executors import ExternalShutdownException, spin_nodes
from zros.node import Node
from zros.qos import QoSProfile
from zros.rotations import quaternion_from_yaw, yaw_from_quaternion
from zros.sim import TURTLEBOT3_IMU, Pose2D, SimError, SimRobot, Simulation, load_world, rasterize, wrap_angle
from zros.sim.gz_topics import RobotTopics, default_topics, gz_key
from zros.sim.model_file import RobotModel, robot_from_xml, turtlebot3_model, turtlebot3_named
from zros.sim.robot import odometry_source
from zros.sim.sdf import SdfError

from interfaces.gazebo_msgs.srv import (DeleteEntity, GetEntityState, GetModelList, GetModelState, SetEntityState,
                                        SetModelState, SpawnEntity)
from interfaces.nav_msgs.srv import GetMap
from interfaces.rcl_interfaces.msg import SetParametersResult
from interfaces.rosgraph_msgs.msg import Clock
from interfaces.ros_gz_interfaces.srv import ControlWorld
from interfaces.std_srvs.srv import Empty

from nodes.turtlebot3_gazebo._robot_io import RobotEndpoints, model_topics, stamp

__all__ = ['GazeboNode', 'main']

#: Behind the wall clock by more than this [s], the pacing gives up catching up.
MAX_LAG = 0.25
PAUSED_CLOCK_PERIOD = 0.1   # [s] wall time between /clock repeats while paused, for late joiners
#: [s] of wall time the simulation runs ahead before it sleeps: each wake-up costs more CPU than
#: a step, so at 1x steps run in batches of up to 20 ms (4 steps); outputs keep exact stamps.
WAKE_PERIOD = 0.02


def _default_model() -> str:
    return os.environ.get('TURTLEBOT3_MODEL', 'burger') or 'burger'


class _Robot:
    """A robot in the world: the simulated body and its topics."""

    def __init__(self, sim_robot: SimRobot, endpoints: RobotEndpoints) -> None:
        self.sim = sim_robot
        self.io = endpoints


class GazeboNode(Node):

    def __init__(self, *, gz: bool = False, **kwargs: Any) -> None:
        super().__init__('gazebo', **kwargs)
        self._gz = gz
        self._lock = threading.RLock()
        self._stop = threading.Event()
        self._wake = threading.Event()
        self._thread: threading.Thread | None = None
        self._robots: dict[str, _Robot] = {}
        world = load_world(self._string('world', 'empty_world'), on_warning=self.get_logger().warn)
        self._world_name = world.name
        self._sim = Simulation(world, seed=self._integer('seed', 0), on_collision=self._on_collision,
                               on_command_timeout=self._on_command_timeout)
        self._rtf = self._number('real_time_factor', 1.0, minimum=0.0)
        self._clock_period_ns = int(1e9 / self._number('publish_rate', 100.0, minimum=1e-3))
        self._paused = bool(self.declare_parameter('paused', False).value)
        self._stamped = bool(self.declare_parameter('enable_stamped_cmd_vel', False).value)
        self._publish_frames = bool(self.declare_parameter('publish_robot_frames', True).value)
        self._cmd_vel_timeout = self._number('cmd_vel_timeout', 0.0, minimum=0.0)
        self._lidar_noise = self._number('lidar_noise_stddev', 0.01, minimum=0.0)
        self._slip = self._number('wheel_slip_stddev', 0.002, minimum=0.0)
        source = self._string('odometry_source', '')
        try:    # '' (the default): as each robot's model file says, WORLD unless it says otherwise
            self._odometry = odometry_source(source) if source else ''
        except ValueError as exc:
            raise CliError(f"parameter 'odometry_source': {exc}") from None
        self._number('map_resolution', 0.05, minimum=1e-4)
        self._run_until_ns: int | None = None
        self._clock_pub = self.create_publisher(Clock, gz_key('/clock') if gz else '/clock', QoSProfile(depth=1))
        self._clock_msg = Clock()
        self.add_on_set_parameters_callback(self._check_parameters)
        self.add_post_set_parameters_callback(self._on_parameters_set)

        if self.declare_parameter('spawn_robot', True).value:
            model = self._string('model', _default_model())
            name = self._string('robot_name', model)
            pose = Pose2D(self._number('x_pose', world.spawn.x), self._number('y_pose', world.spawn.y),
                          self._number('yaw', world.spawn.yaw))
            try:
                self._spawn(name, self._string('robot_namespace', ''), pose, self._publish_frames,
                            self._with_lidar_noise(turtlebot3_model(model)))
            except (SimError, ValueError) as exc:
                raise CliError(f'cannot spawn the robot: {exc}') from None

        self.get_logger().info(f"World '{world.name}' from {world.source or world.name}: {len(world.edges)} wall "
                               f'segments, {len(world.circles)} round obstacles; real_time_factor {self._rtf:g}')
        self._create_services()
        self._schedule_reset()
        self._thread = threading.Thread(target=self._run, name='gzserver-sim', daemon=True)
        self._thread.start()

    # -- parameters ----------------------------------------------------------------------------
    def _number(self, name: str, default: float, *, minimum: float | None = None) -> float:
        value = self.declare_parameter(name, float(default)).value
        try:
            number = float(value)
        except (TypeError, ValueError):
            raise CliError(f"parameter '{name}' must be a number, got {value!r}") from None
        if not math.isfinite(number) or (minimum is not None and number < minimum):
            raise CliError(f"parameter '{name}' must be a finite number"
                           + (f' >= {minimum:g}' if minimum is not None else '') + f', got {value!r}')
        return number

    def _integer(self, name: str, default: int) -> int:
        value = self.declare_parameter(name, default).value
        if isinstance(value, bool) or not isinstance(value, int):
            raise CliError(f"parameter '{name}' must be an integer, got {value!r}")
        return value

    def _string(self, name: str, default: str) -> str:
        return str(self.declare_parameter(name, default).value)

    def _check_parameters(self, parameters: list[Any]) -> SetParametersResult:
        for p in parameters:
            if p.name in ('real_time_factor', 'cmd_vel_timeout', 'map_resolution'):
                try:
                    value = float(p.value)
                except (TypeError, ValueError):
                    return SetParametersResult(successful=False, reason=f'{p.name} must be a number')
                floor = 1e-4 if p.name == 'map_resolution' else 0.0
                if not (math.isfinite(value) and value >= floor):
                    return SetParametersResult(successful=False, reason=f'{p.name} must be >= {floor:g}')
        return SetParametersResult(successful=True)

    def _on_parameters_set(self, parameters: list[Any]) -> None:
        with self._lock:
            for p in parameters:
                if p.name == 'real_time_factor':
                    self._rtf = float(p.value)
                elif p.name == 'cmd_vel_timeout':
                    self._cmd_vel_timeout = float(p.value)
                    for robot in self._robots.values():
                        robot.sim.command_timeout = self._cmd_vel_timeout or None
                elif p.name == 'paused':
                    self._paused = bool(p.value)
        self._wake.set()

    # -- robots -------------------------------------------------------------------------------
    def _spawn(self, name: str, namespace: str, pose: Pose2D, publish_frames: bool, model: RobotModel, *,
               topics: RobotTopics | None = None) -> _Robot:
        """Add a robot and its topics (caller holds the lock, or is the constructor);
        `publish_frames`: publish its fixed and wheel frames (no robot_state_publisher for it);
        `model`: what its model file says (its odometry source unless `odometry_source` is set);
        `topics`: where it talks (else as its Gazebo classic plugins say, under `namespace`)."""
        spec = model.spec
        odometry = self._odometry or model.drive.odometry_source
        topics = topics or model_topics(model, namespace)
        namespace = topics.namespace
        if any(r.io.namespace == namespace for r in self._robots.values()):
            raise SimError(f"namespace '/{namespace}' is already used by another robot; give each "
                           'robot its own robot_namespace')
        sim_robot = self._sim.add_robot(name, pose, spec=spec, lidar=model.lidar, imu=model.imu or TURTLEBOT3_IMU,
                                        slip_stddev=self._slip, odometry=odometry)
        sim_robot.command_timeout = self._cmd_vel_timeout or None
        try:
            endpoints = RobotEndpoints(self, sim_robot, model, topics, stamped_cmd_vel=self._stamped,
                                       publish_frames=publish_frames)
        except Exception:
            self._sim.remove_robot(name)
            raise
        robot = self._robots[name] = _Robot(sim_robot, endpoints)
        endpoints.schedule(self._sim.time_ns)
        where = f"Gazebo topics, commands on '{topics.cmd_vel}'" if self._gz else f"topics under '/{namespace}'"
        endpoints.publish_static_frames()
        endpoints.publish_collisions()
        self.get_logger().info(
            f"Spawned {spec.model} '{name}' at x={pose.x:g} y={pose.y:g} yaw={pose.yaw:g} "
            f"({where}, cmd_vel as {endpoints.cmd_type._TYPE}, {odometry} odometry)")
        return robot

    def _with_lidar_noise(self, model: RobotModel) -> RobotModel:
        """A TurtleBot3 without a model file: its lidar's noise is `lidar_noise_stddev`."""
        return model._replace(lidar=replace(model.lidar, noise_stddev=self._lidar_noise))

    def _on_collision(self, robot: SimRobot) -> None:
        """The simulation says a robot started touching something: count it where benchmarks
        look (`sim/collisions`) and tell the user."""
        entry = self._robots.get(robot.name)
        if entry is not None:
            entry.io.publish_collisions()
        p = robot.pose
        self.get_logger().warn(f"'{robot.name}' collided at x={p.x:.2f} y={p.y:.2f} "
                               f'(collision #{robot.collisions})', throttle_duration_sec=1.0)

    def _on_command_timeout(self, robot: SimRobot) -> None:
        """The watchdog stopped a robot whose commands stopped coming (a lost link, a dead
        controller): say so once, with the simulated time to the step (benchmarks/link.py reads it)."""
        self.get_logger().warn(f"'{robot.name}' stopped: no cmd_vel for {robot.command_timeout:g} s "
                               f'(cmd_vel_timeout) at {self._sim.time_ns / 1e9:.3f} s simulated time')

    # -- services ----------------------------------------------------------------------------
    def _create_services(self) -> None:
        self.create_service(GetMap, '/sim/get_map', self._on_get_map)
        if self._gz:    # Gazebo Sim's world services, on its side: ros_gz_sim's create calls them
            world = f'/world/{self._world_name}'
            self.create_service(SpawnEntity, gz_key(f'{world}/create'), self._on_spawn_entity)
            self.create_service(DeleteEntity, gz_key(f'{world}/remove'), self._on_delete_entity)
            self.create_service(ControlWorld, gz_key(f'{world}/control'), self._on_control_world)
            return
        self.create_service(Empty, '/reset_simulation', self._on_reset_simulation)
        self.create_service(Empty, '/reset_world', self._on_reset_world)
        self.create_service(Empty, '/pause_physics', lambda req, res: self._set_paused(True, res))
        self.create_service(Empty, '/unpause_physics', lambda req, res: self._set_paused(False, res))
        self.create_service(SpawnEntity, '/spawn_entity', self._on_spawn_entity)
        self.create_service(DeleteEntity, '/delete_entity', self._on_delete_entity)
        self.create_service(GetEntityState, '/get_entity_state', self._on_get_entity_state)
        self.create_service(SetEntityState, '/set_entity_state', self._on_set_entity_state)
        self.create_service(GetModelList, '/get_model_list', self._on_get_model_list)
        self.create_service(GetModelState, '/get_model_state', self._on_get_model_state)    # ROS 1's names,
        self.create_service(SetModelState, '/set_model_state', self._on_set_model_state)    # still in courses
        self.create_service(ControlWorld, f'/world/{self._world_name}/control', self._on_control_world)

    def _set_paused(self, paused: bool, response: Any) -> Any:
        with self._lock:
            self._paused = paused
            self._run_until_ns = None
        self._wake.set()
        return response

    def _on_reset_simulation(self, request: Any, response: Any) -> Any:
        with self._lock:
            self._reset_simulation()
        return response

    def _reset_simulation(self) -> None:
        self._sim.reset()
        self._schedule_reset()
        for robot in self._robots.values():
            robot.io.publish_collisions()
        self._publish_clock()
        self._wake.set()

    def _on_reset_world(self, request: Any, response: Any) -> Any:
        with self._lock:
            self._reset_world()
        return response

    def _reset_world(self) -> None:
        """Robots back to where they were spawned, stopped, encoder odometry restarted (world
        odometry is the pose anyway); time goes on."""
        for robot in self._robots.values():
            try:
                self._sim.teleport(robot.sim.name, robot.sim.spawn_pose)
            except SimError as exc:   # another robot stands there now
                self.get_logger().warn(f"reset_world: {exc}; '{robot.sim.name}' stays where it is")
            robot.sim.odom.reset()

    def _on_spawn_entity(self, request: Any, response: Any) -> Any:
        model = turtlebot3_named(request.xml, _default_model())
        robot_model = self._with_lidar_noise(turtlebot3_model(model))
        name = request.name or f'{model}_{len(self._robots)}'
        if '<model' in request.xml or '<robot' in request.xml:
            try:
                robot_model = robot_from_xml(request.xml, fallback=_default_model(), source=f'<{name} XML>',
                                             world=self._world_name)
            except SdfError as exc:
                response.success, response.status_message = False, str(exc)
                return response
            if robot_model.warning:
                self.get_logger().warn(robot_model.warning)
        topics = None
        if self._gz:    # its topics on Gazebo's side, as its gz-sim plugins name them
            topics = robot_model.topics or default_topics(name, self._world_name)
            topics = topics._replace(**{key: gz_key(getattr(topics, key))
                                        for key in ('cmd_vel', 'odom', 'tf', 'joint_states', 'scan', 'imu')})
        p = request.initial_pose
        pose = Pose2D(p.position.x, p.position.y, _yaw(p.orientation))
        with self._lock:
            try:
                # As Gazebo: only what the model's plugins publish (robot_state_publisher has the rest).
                self._spawn(name, request.robot_namespace, pose, False, robot_model, topics=topics)
            except (SimError, ValueError) as exc:
                response.success, response.status_message = False, str(exc)
                return response
        response.success = True
        response.status_message = f'SpawnEntity: Successfully spawned entity [{name}]'   # Gazebo's words
        return response

    def _entity_name(self, name: str) -> str:
        """The robot `name` means: its own name, or `turtlebot3_<model>` for a TurtleBot3 spawned
        under its model's name (TurtleBot3's launch spawns `burger`; courses ask for
        `turtlebot3_burger`). Unknown names come back unchanged (caller holds the lock)."""
        if name not in self._robots and name.startswith('turtlebot3_'):
            short = name.removeprefix('turtlebot3_')
            if short in self._robots and self._robots[short].sim.spec.model == short:
                return short
        return name

    def _on_delete_entity(self, request: Any, response: Any) -> Any:
        with self._lock:
            name = self._entity_name(request.name)
            robot = self._robots.pop(name, None)
            if robot is None:
                response.success = False
                response.status_message = f"no entity named '{request.name}'"
                return response
            self._sim.remove_robot(name)
            robot.io.destroy()
        response.success, response.status_message = True, f"deleted '{request.name}'"
        return response

    def _true_state(self, name: str, header: Any, pose_msg: Any, twist_msg: Any) -> bool:
        """Fill a header and a Pose and Twist (world frame) with a robot's true state; False if
        there is no such robot."""
        with self._lock:
            robot = self._robots.get(self._entity_name(name))
            stamp(header, self._sim.time_ns)
            header.frame_id = 'world'
            if robot is None:
                return False
            pose, (linear, angular) = robot.sim.pose, robot.sim.velocity
        pose_msg.position.x, pose_msg.position.y = pose.x, pose.y
        o = pose_msg.orientation
        o.x, o.y, o.z, o.w = quaternion_from_yaw(pose.yaw)
        twist_msg.linear.x = linear * math.cos(pose.yaw)
        twist_msg.linear.y = linear * math.sin(pose.yaw)
        twist_msg.angular.z = angular
        return True

    def _on_get_entity_state(self, request: Any, response: Any) -> Any:
        state = response.state
        response.success = self._true_state(request.name, response.header, state.pose, state.twist)
        if response.success:
            state.name, state.reference_frame = request.name, 'world'
        return response

    def _on_get_model_state(self, request: Any, response: Any) -> Any:
        response.success = self._true_state(request.model_name, response.header, response.pose, response.twist)
        response.status_message = ('GetModelState: got properties' if response.success
                                   else f"GetModelState: model '{request.model_name}' does not exist")
        return response

    def _teleport(self, name: str, pose_msg: Any) -> tuple[bool, str]:
        pose = Pose2D(pose_msg.position.x, pose_msg.position.y, _yaw(pose_msg.orientation))
        with self._lock:
            try:
                self._sim.teleport(self._entity_name(name), pose)
            except SimError as exc:
                self.get_logger().warn(f'set_entity_state: {exc}')
                return False, str(exc)
        return True, f"moved '{name}'"

    def _on_set_entity_state(self, request: Any, response: Any) -> Any:
        response.success, _ = self._teleport(request.state.name, request.state.pose)
        return response

    def _on_set_model_state(self, request: Any, response: Any) -> Any:
        response.success, response.status_message = self._teleport(request.model_state.model_name,
                                                                   request.model_state.pose)
        return response

    def _on_get_model_list(self, request: Any, response: Any) -> Any:
        with self._lock:
            stamp(response.header, self._sim.time_ns)
            response.model_names = list(self._robots)
        response.success = True
        return response

    def _on_control_world(self, request: Any, response: Any) -> Any:
        control = request.world_control
        with self._lock:
            if control.seed:
                self._sim.seed = int(control.seed)    # used from the next reset
            reset = control.reset
            if reset.all:
                self._reset_simulation()
            elif reset.model_only:
                self._reset_world()
            elif reset.time_only:
                self._sim.time_ns = 0
                self._schedule_reset()
            self._paused = bool(control.pause)
            steps = int(control.multi_step) or (1 if control.step else 0)
            for _ in range(steps):
                self._step()
            target = control.run_to_sim_time.sec * 1_000_000_000 + control.run_to_sim_time.nanosec
            self._run_until_ns = target if target > self._sim.time_ns else None
            if self._run_until_ns is not None:
                self._paused = False
        self._wake.set()
        response.success = True
        return response

    def _on_get_map(self, request: Any, response: Any) -> Any:
        resolution = float(self.get_parameter('map_resolution').value)
        raster = rasterize(self._sim.world, resolution)
        grid = response.map
        with self._lock:
            stamp(grid.header, self._sim.time_ns)
        grid.header.frame_id = 'map'
        grid.info.resolution = raster.resolution
        grid.info.width, grid.info.height = raster.width, raster.height
        grid.info.origin.position.x, grid.info.origin.position.y = raster.origin
        grid.data = raster.occupancy_data()
        return response

    # -- the simulation thread --------------------------------------------------------------------
    def _schedule_reset(self) -> None:
        """Outputs fall due one period after now (a scan at 0.2 s, 0.4 s, ... of simulated time)."""
        now = self._sim.time_ns
        self._next_clock = now + self._clock_period_ns
        for robot in self._robots.values():
            robot.io.schedule(now)
        self._anchor = None    # the pacing restarts from here

    def _step(self) -> None:
        """One physics step and whatever outputs fall due (caller holds the lock)."""
        self._sim.step()
        now = self._sim.time_ns
        if now >= self._next_clock:
            self._publish_clock()
            self._next_clock += self._clock_period_ns
        for robot in self._robots.values():
            robot.io.publish_due(now)
        if self._run_until_ns is not None and now >= self._run_until_ns:
            self._paused, self._run_until_ns = True, None

    def _publish_clock(self) -> None:
        stamp(self._clock_msg, self._sim.time_ns, field='clock')
        self._clock_pub.publish(self._clock_msg)

    def _run(self) -> None:
        behind_warned = False
        last_paused_clock = 0.0
        while not self._stop.is_set():
            try:
                with self._lock:
                    paused, rtf = self._paused, self._rtf
                    if not paused:
                        self._step()
                        sim_ns = self._sim.time_ns
                        if self._anchor is None or self._anchor[2] != rtf:
                            self._anchor = (time.monotonic(), sim_ns, rtf)
                    else:
                        self._anchor = None
                        now = time.monotonic()
                        if now - last_paused_clock >= PAUSED_CLOCK_PERIOD:
                            self._publish_clock()
                            last_paused_clock = now
            except Exception as exc:  # noqa: BLE001 - a dying sim thread would freeze the world silently
                if self._stop.is_set() or not self.context.ok():
                    return
                self.get_logger().error(f'simulation step failed: {exc}')
                raise
            if paused:
                self._wake.wait(PAUSED_CLOCK_PERIOD)
                self._wake.clear()
                continue
            if rtf <= 0.0:
                continue
            wall0, sim0, _ = self._anchor
            delay = wall0 + (sim_ns - sim0) / 1e9 / rtf - time.monotonic()
            if delay > WAKE_PERIOD:
                if self._wake.wait(delay):
                    self._wake.clear()
            elif delay < -MAX_LAG:
                if not behind_warned:
                    behind_warned = True
                    self.get_logger().warn(f'cannot keep up with real_time_factor {rtf:g}: the simulation '
                                           'runs slower than asked (it never skips physics)')
                with self._lock:
                    self._anchor = None

    def destroy_node(self) -> None:
        self._stop.set()
        self._wake.set()
        if self._thread is not None and self._thread.is_alive() and threading.current_thread() is not self._thread:
            self._thread.join(timeout=2.0)
        super().destroy_node()


def _yaw(q: Any) -> float:
    """Yaw [rad] in [-pi, pi) of a geometry_msgs/Quaternion (an all-zero quaternion counts as none)."""
    return wrap_angle(yaw_from_quaternion(q.x, q.y, q.z, q.w))


def main(args: list[str] | None = None) -> None:
    try:
        with zros.init(args=args):
            spin_nodes(GazeboNode(), num_threads=4)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass


if __name__ == '__main__':
    main(sys.argv)
