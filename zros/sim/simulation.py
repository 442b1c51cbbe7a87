"""The headless simulator: a world, TurtleBot3s driving in it on pymunk, their sensors, a clock.

No Zenoh, no threads, no wall clock: time moves only when `step()` is called, in fixed steps
(5 ms by default), and every random number comes from generators seeded by `seed`, one stream per
robot and sensor. The same world, seed and command sequence therefore give the same trajectory,
bit for bit, however fast or slow the caller runs. The zros node (`turtlebot3_gazebo gzserver`)
is this class plus topics, services and pacing; benchmarks drive it directly:

    from zros.sim import Simulation, load_world
    sim = Simulation(load_world('turtlebot3_world'), seed=1)
    robot = sim.add_robot('burger')                     # at the world's spawn pose
    robot.command(0.2, 0.0)                             # [m/s], [rad/s]; holds until changed
    sim.step(5.0)                                       # 5 s of simulated time
    robot.pose, robot.odometry(), robot.scan()          # truth, odometry (here the truth too), lidar

Odometry is Gazebo's `world` source unless `add_robot(..., odometry='encoder')` asks for wheel
odometry that starts at (0, 0) and drifts (zros.sim.robot); benchmarks of SLAM and localization
ask for it, to be scored against a robot's real errors.

Physics: each robot is a pymunk disc (`RobotSpec.body_radius`) whose velocity is set every step
from its diff drive (at the step's mid heading, so straight and curved motion integrate the way
the odometry does); obstacles are static segments and discs; pymunk's contact solver stops a
robot at a wall, and a robot sliding along a wall keeps only the tangential part of its motion.
A collision is a robot going from touching nothing to touching something; each is counted.
The world's pushable bodies (non-static models of an SDF world) are dynamic pymunk bodies with
their mass: a robot drives them before it (its own speed is commanded, so it wins any push),
the floor's friction is a damping that stops a body within about a second once nothing pushes
it (`BODY_DAMPING`), and lidars see them where they are.
Not thread-safe: one caller at a time.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

import numpy as np
import pymunk

from zros.errors import ZrosError
from zros.rotations import wrap_angle
from zros.sim.raster import OccupancyRaster, rasterize
from zros.sim.robot import BURGER, DiffDrive, RobotSpec, WheelOdometry, odometry_source
from zros.sim.sensors import GRAVITY, LDS_01, TURTLEBOT3_IMU, ImuReading, ImuSpec, LidarSpec, scan_ranges
from zros.sim.world import Body, Pose2D, World

__all__ = ['Simulation', 'SimRobot', 'OdometryState', 'SimError', 'DEFAULT_DT', 'DEFAULT_SLIP_STDDEV',
           'BODY_DAMPING']

DEFAULT_DT = 0.005               # [s] physics step
DEFAULT_SLIP_STDDEV = 0.002      # [m per sqrt(m)] wheel odometry error
_ROBOT, _OBSTACLE = 1, 2         # pymunk collision types
#: Fraction of a pushable body's speed left after one second without a push (floor friction).
BODY_DAMPING = 0.01


class SimError(ZrosError, ValueError):
    """A request the simulator refuses (unknown or duplicate robot, a pose inside an obstacle)."""


@dataclass(frozen=True)
class OdometryState:
    """Odometry in the `odom` frame: pose x, y [m], yaw [rad]; body-frame speeds [m/s], [rad/s]."""
    x: float
    y: float
    yaw: float
    linear: float
    angular: float


class SimRobot:
    """One robot in a Simulation. Made by `Simulation.add_robot`, never directly."""

    def __init__(self, sim: 'Simulation', name: str, index: int, spec: RobotSpec, pose: Pose2D,
                 lidar: LidarSpec, imu: ImuSpec, slip_stddev: float, odometry: str) -> None:
        self.name = name
        #: 'world' (odom is the world frame, exact) or 'encoder' (wheel odometry from the spawn pose).
        self.odometry_source = odometry_source(odometry)
        self.spec = spec
        self.lidar = lidar
        self.imu_spec = imu
        self.spawn_pose = pose
        #: Seconds without a new command after which the robot stops at once (a base's watchdog);
        #: None: commands hold forever.
        self.command_timeout: float | None = None
        self.collisions = 0
        self._sim = sim
        self._index = index
        self._slip_stddev = slip_stddev
        self._contacts = 0
        self._body: pymunk.Body | None = None
        self._build(pose)

    def _build(self, pose: Pose2D) -> None:
        """(Re)create the physics body and every piece of state, seeded afresh."""
        seed = self._sim.seed
        self._odom_rng = np.random.default_rng([seed, self._index, 0])
        self._lidar_rng = np.random.default_rng([seed, self._index, 1])
        self._imu_rng = np.random.default_rng([seed, self._index, 2])
        self.drive = DiffDrive(self.spec)
        # With world odometry the wheels only turn the joints, which Gazebo reports exactly.
        slip = self._slip_stddev if self.odometry_source == 'encoder' else 0.0
        self.odom = WheelOdometry(self.spec, self._odom_rng, slip)
        self._last_command_ns = self._sim.time_ns
        self._timed_out = False
        self._velocity = (0.0, 0.0)
        self._acceleration = 0.0
        body = pymunk.Body(self.spec.mass, math.inf)
        body.position = (pose.x, pose.y)
        body.angle = pose.yaw
        shape = pymunk.Circle(body, self.spec.body_radius)
        shape.friction = 0.0
        shape.elasticity = 0.0
        shape.collision_type = _ROBOT
        shape.robot = self        # the collision callbacks find the robot through its shape
        body.velocity_func = self._set_velocity
        self._drive_speeds = (0.0, 0.0)
        self._body, self._shape = body, shape
        self._contacts = 0
        self._was_touching = False

    # -- commands --------------------------------------------------------------------------
    def command(self, linear: float, angular: float) -> None:
        """Drive at `linear` [m/s] and `angular` [rad/s] (clamped to the limits) until the next
        command, or until `command_timeout` passes. ValueError for NaN or infinite values."""
        if not (math.isfinite(linear) and math.isfinite(angular)):
            raise ValueError(f'command must be finite, got linear={linear}, angular={angular}')
        self.drive.set_target(linear, angular)
        self._last_command_ns = self._sim.time_ns
        self._timed_out = False

    # -- state -----------------------------------------------------------------------------
    @property
    def pose(self) -> Pose2D:
        """Ground truth: base_footprint in the world frame, yaw wrapped to [-pi, pi)."""
        x, y = self._body.position
        return Pose2D(float(x), float(y), wrap_angle(float(self._body.angle)))

    @property
    def velocity(self) -> tuple[float, float]:
        """Ground truth body-frame (linear [m/s], angular [rad/s]) over the last step."""
        return self._velocity

    @property
    def in_contact(self) -> bool:
        return self._contacts > 0

    def odometry(self) -> OdometryState:
        """The pose in `odom` and the body's speeds: the true ones with `world` odometry, the
        wheels' integration (from (0, 0) at spawn or reset) with `encoder` odometry."""
        if self.odometry_source == 'world':
            pose, (linear, angular) = self.pose, self._velocity
            return OdometryState(pose.x, pose.y, pose.yaw, linear, angular)
        o = self.odom
        return OdometryState(o.x, o.y, o.yaw, o.linear, o.angular)

    @property
    def wheel_positions(self) -> tuple[float, float]:
        """Left and right wheel joint angles [rad], as the encoders count them."""
        return tuple(self.odom.wheel_positions)  # type: ignore[return-value]

    @property
    def wheel_velocities(self) -> tuple[float, float]:
        return tuple(self.odom.wheel_velocities)  # type: ignore[return-value]

    def sensor_pose(self, mount: tuple[float, float, float]) -> tuple[float, float, float]:
        """World (x, y, yaw) of a point mounted at `mount` (base_link x, y, z)."""
        p = self.pose
        c, s = math.cos(p.yaw), math.sin(p.yaw)
        return (p.x + c * mount[0] - s * mount[1], p.y + s * mount[0] + c * mount[1], p.yaw)

    def scan(self, *, noise: bool = True) -> np.ndarray:
        """A lidar scan from the current pose: (samples,) float32 ranges [m] (+inf: no return,
        -inf: too close). Other robots show as their lidar housings."""
        return self._sim._scan(self, noise)

    def imu(self) -> ImuReading:
        linear, angular = self._velocity
        g, a = self.imu_spec.gyro_noise_stddev, self.imu_spec.accel_noise_stddev
        n = self._imu_rng.standard_normal(6).tolist()
        return ImuReading(self.pose.yaw, (g * n[0], g * n[1], angular + g * n[2]),
                          (self._acceleration + a * n[3], linear * angular + a * n[4], GRAVITY + a * n[5]))

    # -- stepping (called by Simulation) -------------------------------------------------------
    def _before_step(self, dt: float) -> bool:
        """Set this step's wheel speeds; True if the command timeout stopped a moving robot now.

        The timeout is a real base's watchdog (OpenCR's firmware), not a command: it zeroes the
        wheels at once, without the acceleration limit that paces commanded changes, so a
        robot that loses its commands stops `command_timeout` after the last one, to a step."""
        stopped = False
        timeout = self.command_timeout
        if (timeout is not None and not self._timed_out
                and self._sim.time_ns - self._last_command_ns > timeout * 1e9):
            self._timed_out = True
            stopped = self.drive.target != (0.0, 0.0) or self.drive.wheel_speeds != (0.0, 0.0)
            self.drive.stop()
        self._drive_speeds = self.drive.update(dt)
        self._start = (self._body.position, self._body.angle)
        return stopped

    def _set_velocity(self, body: pymunk.Body, gravity: object, damping: float, dt: float) -> None:
        """pymunk's velocity function: runs after positions move and before contacts are
        solved, so the solver trims the commanded velocity before the next step moves the body
        (set before `space.step`, it would carry the body into the wall first)."""
        linear, angular = self._drive_speeds
        heading = body.angle + angular * dt / 2.0
        body.velocity = (linear * math.cos(heading), linear * math.sin(heading))
        body.angular_velocity = angular

    def _after_step(self, dt: float) -> None:
        (x0, y0), yaw0 = self._start
        x1, y1 = self._body.position
        turn = float(self._body.angle - yaw0)
        heading = yaw0 + turn / 2.0
        forward = (x1 - x0) * math.cos(heading) + (y1 - y0) * math.sin(heading)
        self.odom.update(forward, turn, dt)
        linear = forward / dt
        self._acceleration = (linear - self._velocity[0]) / dt
        self._velocity = (linear, turn / dt)

    def _touch(self, delta: int) -> None:
        self._contacts = max(0, self._contacts + delta)

    def _count_collision(self) -> bool:
        """After a step: whether the robot started touching something during it (passing from
        one wall segment to the next within a step is not a new collision)."""
        touching = self._contacts > 0
        started, self._was_touching = touching and not self._was_touching, touching
        if started:
            self.collisions += 1
        return started


class Simulation:
    """A world with robots in it, stepped in fixed time steps. See the module docstring.

    Args:
        world: the obstacles (`load_world(...)`).
        dt: physics step [s].
        seed: seeds every noise generator (per robot, per sensor).
        on_collision: called with the robot, after the step, each time one starts touching something.
        on_command_timeout: called with the robot, before the step (at `time`), each time its
            `command_timeout` stops it while it was moving or commanded to.
    """

    def __init__(self, world: World, *, dt: float = DEFAULT_DT, seed: int = 0,
                 on_collision: Callable[[SimRobot], None] | None = None,
                 on_command_timeout: Callable[[SimRobot], None] | None = None) -> None:
        if not dt > 0:
            raise ValueError(f'dt must be > 0, got {dt}')
        self.world = world
        self.dt = float(dt)
        self.dt_ns = int(round(dt * 1e9))
        self.seed = int(seed)
        self.time_ns = 0
        self.robots: dict[str, SimRobot] = {}
        self.on_collision = on_collision
        self.on_command_timeout = on_command_timeout
        self._next_index = 0
        self._build_space()

    @property
    def time(self) -> float:
        """Simulated time [s] since start or reset."""
        return self.time_ns / 1e9

    def _build_space(self) -> None:
        space = pymunk.Space()
        space.gravity = (0.0, 0.0)
        # Metres, not pixels: pymunk's default slop would let a robot 10 cm into a wall, and a
        # strong bias removes any overlap within a step or two.
        space.collision_slop = 0.0002
        space.collision_bias = 1e-30
        for x1, y1, x2, y2 in self.world.edges:
            self._add_static(space, pymunk.Segment(space.static_body, (x1, y1), (x2, y2), 0.0))
        for cx, cy, r in self.world.circles:
            self._add_static(space, pymunk.Circle(space.static_body, r, (cx, cy)))
        self.bodies: dict[str, pymunk.Body] = {}
        for body in self.world.bodies:
            self.bodies[body.name] = self._add_body(space, body)
        space.on_collision(_ROBOT, _OBSTACLE, begin=_begin, separate=_separate)
        space.on_collision(_ROBOT, _ROBOT, begin=_begin, separate=_separate)
        self.space = space

    @staticmethod
    def _add_body(space: pymunk.Space, body: 'Body') -> pymunk.Body:
        """A pushable body: convex polygons (hulls) and circles about their common centroid."""
        points = [loop for loop in body.polygons] + [c[None, :2] for c in body.circles]
        centre = np.vstack(points).mean(axis=0)
        shapes_of = []
        moment = 0.0
        share = body.mass / max(1, len(body.polygons) + len(body.circles))
        for loop in body.polygons:
            vertices = [tuple(v) for v in (loop - centre)]
            moment += pymunk.moment_for_poly(share, vertices)
            shapes_of.append(lambda b, v=vertices: pymunk.Poly(b, v))
        for cx, cy, r in body.circles:
            offset = (cx - centre[0], cy - centre[1])
            moment += pymunk.moment_for_circle(share, 0.0, r, offset)
            shapes_of.append(lambda b, r=r, o=offset: pymunk.Circle(b, r, o))
        dynamic = pymunk.Body(body.mass, moment)
        dynamic.position = tuple(centre)
        dynamic.velocity_func = _floor_friction
        space.add(dynamic)
        for make in shapes_of:
            shape = make(dynamic)
            shape.friction, shape.elasticity, shape.collision_type = 0.0, 0.0, _OBSTACLE
            space.add(shape)
        return dynamic

    def body_pose(self, name: str) -> Pose2D:
        """Where a pushable body's centroid is now, and how far it has turned [rad] since the start."""
        try:
            body = self.bodies[name]
        except KeyError:
            raise SimError(f"no pushable body named '{name}' (bodies: {', '.join(self.bodies) or 'none'})") from None
        return Pose2D(float(body.position.x), float(body.position.y), wrap_angle(float(body.angle)))

    @staticmethod
    def _add_static(space: pymunk.Space, shape: pymunk.Shape) -> None:
        shape.friction = 0.0
        shape.elasticity = 0.0
        shape.collision_type = _OBSTACLE
        space.add(shape)

    # -- robots ------------------------------------------------------------------------------
    def add_robot(self, name: str = 'burger', pose: Pose2D | tuple[float, float, float] | None = None, *,
                  spec: RobotSpec = BURGER, lidar: LidarSpec = LDS_01, imu: ImuSpec = TURTLEBOT3_IMU,
                  slip_stddev: float = DEFAULT_SLIP_STDDEV, odometry: str = 'world') -> SimRobot:
        """Put a robot in the world at `pose` (x, y, yaw; default: the world's spawn pose).

        Args:
            odometry: 'world' (Gazebo's default: odom is the world frame, exact) or 'encoder'
                (wheel odometry from (0, 0) at `pose`, drifting by `slip_stddev`); 1 and 0 too.

        Raises:
            SimError: the name is taken, or the robot would overlap an obstacle or a robot.
            ValueError: an unknown odometry source.
        """
        if name in self.robots:
            raise SimError(f"a robot named '{name}' already exists")
        pose = self.world.spawn if pose is None else Pose2D(*pose) if not isinstance(pose, Pose2D) else pose
        self._check_free(pose, spec.body_radius, None)
        robot = SimRobot(self, name, self._next_index, spec, pose, lidar, imu, slip_stddev, odometry)
        self._next_index += 1
        self.space.add(robot._body, robot._shape)
        self.robots[name] = robot
        return robot

    def remove_robot(self, name: str) -> None:
        robot = self.robot(name)
        self.space.remove(robot._body, robot._shape)
        del self.robots[name]

    def robot(self, name: str) -> SimRobot:
        try:
            return self.robots[name]
        except KeyError:
            raise SimError(f"no robot named '{name}' (robots: {', '.join(self.robots) or 'none'})") from None

    def teleport(self, name: str, pose: Pose2D | tuple[float, float, float]) -> None:
        """Move a robot (Gazebo's set_entity_state): stopped at `pose`. Encoders do not see the
        jump (encoder odometry goes on from where it was); world odometry is the new pose."""
        robot = self.robot(name)
        pose = pose if isinstance(pose, Pose2D) else Pose2D(*pose)
        self._check_free(pose, robot.spec.body_radius, robot)
        robot._body.position = (pose.x, pose.y)
        robot._body.angle = pose.yaw
        robot._body.velocity = (0.0, 0.0)
        robot.drive.stop()
        robot._velocity = (0.0, 0.0)
        self.space.reindex_shapes_for_body(robot._body)

    def _check_free(self, pose: Pose2D, radius: float, moving: SimRobot | None) -> None:
        for v in (pose.x, pose.y, pose.yaw):
            if not math.isfinite(v):
                raise SimError(f'pose must be finite, got ({pose.x}, {pose.y}, {pose.yaw})')
        if self.world.collides(pose.x, pose.y, radius):
            raise SimError(f'({pose.x:g}, {pose.y:g}) is inside or within {radius:g} m of an obstacle')
        for other in self.robots.values():
            if other is not moving:
                p = other.pose
                if math.hypot(p.x - pose.x, p.y - pose.y) < radius + other.spec.body_radius:
                    raise SimError(f"({pose.x:g}, {pose.y:g}) overlaps robot '{other.name}'")

    def reset(self) -> None:
        """Back to time 0 with every robot at its spawn pose, stopped, with fresh odometry and
        noise generators seeded as at the start (Gazebo's reset_simulation)."""
        self.time_ns = 0
        self._build_space()
        for robot in self.robots.values():
            robot._build(robot.spawn_pose)
            robot.collisions = 0
            self.space.add(robot._body, robot._shape)

    # -- time ------------------------------------------------------------------------------
    def step(self, duration: float | None = None, *, steps: int | None = None) -> int:
        """Advance by `duration` [s] (rounded to whole steps) or by `steps` steps (default one).
        Returns the number of steps taken."""
        if duration is not None and steps is not None:
            raise ValueError('give duration or steps, not both')
        count = 1 if duration is None and steps is None else (
            int(steps) if steps is not None else int(round(duration / self.dt)))
        for _ in range(count):
            self._step_once()
        return count

    def _step_once(self) -> None:
        dt = self.dt
        robots = list(self.robots.values())
        for robot in robots:
            if robot._before_step(dt) and self.on_command_timeout is not None:
                self.on_command_timeout(robot)
        self.space.step(dt)
        self.time_ns += self.dt_ns
        for robot in robots:
            robot._after_step(dt)
            if robot._count_collision() and self.on_collision is not None:
                self.on_collision(robot)

    # -- sensing ---------------------------------------------------------------------------
    def _scan(self, robot: SimRobot, noise: bool) -> np.ndarray:
        x, y, yaw = robot.sensor_pose(robot.spec.lidar_mount)
        yaw += robot.spec.lidar_yaw
        circles, edges = self.world.circles, self.world.edges
        others = [o for o in self.robots.values() if o is not robot]
        if others:
            housings = [(*o.sensor_pose(o.spec.lidar_mount)[:2], o.spec.lidar_housing_radius) for o in others]
            circles = np.vstack([circles, np.array(housings)])
        if self.bodies:
            moved_edges, moved_circles = self._body_geometry()
            edges, circles = np.vstack([edges, moved_edges]), np.vstack([circles, moved_circles])
        return scan_ranges(robot.lidar, (x, y, yaw), edges, circles, robot._lidar_rng if noise else None)

    def _body_geometry(self) -> tuple[np.ndarray, np.ndarray]:
        """The pushable bodies where they are now: edges (N, 4) and circles (M, 3)."""
        edges, circles = [np.zeros((0, 4))], [np.zeros((0, 3))]
        for body in self.bodies.values():
            for shape in body.shapes:
                if isinstance(shape, pymunk.Poly):
                    loop = np.array([tuple(body.local_to_world(v)) for v in shape.get_vertices()])
                    edges.append(np.hstack([loop, np.roll(loop, -1, axis=0)]))
                else:
                    centre = body.local_to_world(shape.offset)
                    circles.append(np.array([[centre.x, centre.y, shape.radius]]))
        return np.vstack(edges), np.vstack(circles)

    def occupancy(self, resolution: float, **kwargs: object) -> OccupancyRaster:
        """The world's exact ground-truth occupancy grid (see zros.sim.raster.rasterize)."""
        return rasterize(self.world, resolution, **kwargs)  # type: ignore[arg-type]


def _floor_friction(body: pymunk.Body, gravity: object, damping: float, dt: float) -> None:
    """A pushable body's velocity function: the floor slows it (BODY_DAMPING per second)."""
    pymunk.Body.update_velocity(body, (0.0, 0.0), BODY_DAMPING ** dt, dt)


def _robots_of(arbiter: pymunk.Arbiter) -> list[SimRobot]:
    return [s.robot for s in arbiter.shapes if getattr(s, 'robot', None) is not None]


def _begin(arbiter: pymunk.Arbiter, space: pymunk.Space, data: object) -> None:
    for robot in _robots_of(arbiter):
        robot._touch(+1)


def _separate(arbiter: pymunk.Arbiter, space: pymunk.Space, data: object) -> None:
    for robot in _robots_of(arbiter):
        robot._touch(-1)
