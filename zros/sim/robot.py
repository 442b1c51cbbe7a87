"""TurtleBot3 and TurtleBot4 models and their drive: the numbers, the differential-drive law, wheel odometry.

Numbers are TurtleBot3's (URDF, Gazebo model.sdf, teleop limits; see the reference digest):
wheel radius 0.033 m, wheel separation 0.160 m (burger), speed limits 0.22 m/s and 2.84 rad/s,
wheel acceleration limited to 1.0 m/s^2 as Gazebo's diff-drive plugin does.

The TurtleBot4 (`TURTLEBOT4`) is a Create 3 base with an RPLIDAR A1 on its shell, as Nav2's
nav2_minimal_tb4_description states it for Gazebo Sim: wheel separation 0.233 m, wheel radius
0.03575 m, limits 0.5 m/s, 2.0 rad/s and 2 m/s^2, a 0.164 m body disc, base_link on the floor
(base_footprint coincides with it), the lidar 0.193 m up and turned a quarter turn left
(`lidar_yaw`: its 0 rad beam points along base_link's +y). zros.sim.model_file picks it for a
model whose diff-drive plugin has its wheels.

The body is a disc around base_footprint (`body_radius`): it covers the wheels and the lidar, so
turning in place never touches anything; the burger's square plate reaches 0.124 m at its back
corners, a simplification worth knowing when a robot backs into a corner.

Odometry has the two sources of Gazebo's diff-drive plugin (`odometry_source`):
- `world` (the plugin's default, and so the TurtleBot3 model's): the body's true pose in the
  world frame, exact, so a robot spawned at (-2.0, -0.5) reports /odom (-2.0, -0.5), and maps
  made from it share the world's (and the course's) coordinates;
- `encoder`: integrated from the wheels from (0, 0) at the spawn pose, as on the real robot.
  Each wheel's travel is measured with a random error whose variance grows with the distance
  rolled (`slip_stddev` [m per sqrt(m)]: after 1 m the error's standard deviation is
  `slip_stddev` m), so odometry drifts like a real robot's and does not depend on the step size.
  Encoders see the body's real motion: a robot pushed sideways along a wall, or stopped by one,
  moves without its wheels telling.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from zros.rotations import wrap_angle

__all__ = ['RobotSpec', 'BURGER', 'WAFFLE', 'WAFFLE_PI', 'TURTLEBOT4', 'robot_spec', 'DiffDrive', 'WheelOdometry',
           'clamp', 'integrate_twist', 'ODOMETRY_SOURCES', 'odometry_source']

#: Gazebo's diff-drive `odometry_source` values by their number: 0 ENCODER, 1 WORLD.
ODOMETRY_SOURCES = ('encoder', 'world')


@dataclass(frozen=True)
class RobotSpec:
    """A differential-drive robot's geometry and limits. Lengths [m], speeds [m/s], [rad/s].

    Mount points are (x, y, z) in base_link; base_link sits `base_height` above base_footprint.
    """
    model: str
    wheel_radius: float
    wheel_separation: float
    max_linear: float
    max_angular: float
    max_wheel_acceleration: float      # [m/s^2] at the wheel rim
    body_radius: float                 # the collision disc around base_footprint
    base_height: float                 # base_footprint -> base_link, z
    lidar_mount: tuple[float, float, float]
    lidar_housing_radius: float        # what another robot's lidar sees of this one
    imu_mount: tuple[float, float, float]
    wheel_mounts: tuple[tuple[float, float, float], tuple[float, float, float]]   # left, right
    caster_mounts: tuple[tuple[float, float, float], ...]
    mass: float = 1.0                  # [kg]
    lidar_yaw: float = 0.0             # [rad] the lidar frame's yaw in base_link


BURGER = RobotSpec(
    model='burger', wheel_radius=0.033, wheel_separation=0.160, max_linear=0.22, max_angular=2.84,
    max_wheel_acceleration=1.0, body_radius=0.105, base_height=0.010,
    lidar_mount=(-0.032, 0.0, 0.172), lidar_housing_radius=0.055, imu_mount=(-0.032, 0.0, 0.068),
    wheel_mounts=((0.0, 0.08, 0.023), (0.0, -0.08, 0.023)), caster_mounts=((-0.081, 0.0, -0.004),),
    mass=1.0)

WAFFLE = RobotSpec(
    model='waffle', wheel_radius=0.033, wheel_separation=0.287, max_linear=0.26, max_angular=1.82,
    max_wheel_acceleration=1.0, body_radius=0.22, base_height=0.010,
    lidar_mount=(-0.064, 0.0, 0.122), lidar_housing_radius=0.055, imu_mount=(0.0, 0.0, 0.068),
    wheel_mounts=((0.0, 0.144, 0.023), (0.0, -0.144, 0.023)),
    caster_mounts=((-0.177, -0.064, -0.004), (-0.177, 0.064, -0.004)), mass=1.8)

WAFFLE_PI = RobotSpec(**{**WAFFLE.__dict__, 'model': 'waffle_pi'})

#: Create 3 base (wheels, caster, IMU) + TurtleBot4 shell with the RPLIDAR A1 (rplidar_link).
TURTLEBOT4 = RobotSpec(
    model='turtlebot4', wheel_radius=0.03575, wheel_separation=0.233, max_linear=0.5, max_angular=2.0,
    max_wheel_acceleration=2.0, body_radius=0.164, base_height=0.0,
    lidar_mount=(-0.04, 0.0, 0.1929), lidar_housing_radius=0.12, imu_mount=(0.0506, 0.0437, 0.0844),
    wheel_mounts=((0.0, 0.1165, 0.0402), (0.0, -0.1165, 0.0402)), caster_mounts=((0.125, 0.0, 0.0139),),
    mass=3.4, lidar_yaw=math.pi / 2)

_MODELS = {spec.model: spec for spec in (BURGER, WAFFLE, WAFFLE_PI)}


def robot_spec(model: str) -> RobotSpec:
    """The spec of a TurtleBot3 model by its TURTLEBOT3_MODEL name; ValueError if unknown."""
    try:
        return _MODELS[model]
    except KeyError:
        raise ValueError(f"unknown TurtleBot3 model '{model}' (known: {', '.join(_MODELS)})") from None


def odometry_source(value: object) -> str:
    """'world' or 'encoder' from a name or Gazebo's number (1, 0, '1', '0'); ValueError otherwise."""
    text = str(value).strip().lower()
    if text in ('0', '1'):
        return ODOMETRY_SOURCES[int(text)]
    if text in ODOMETRY_SOURCES:
        return text
    raise ValueError(f"odometry_source must be 'world' (1) or 'encoder' (0), got {value!r}")


def clamp(value: float, limit: float) -> float:
    return max(-limit, min(limit, value))


class DiffDrive:
    """Turns a (linear, angular) command into wheel rim speeds, within the robot's limits.

    The command is clamped to the speed limits; each wheel then moves towards its target speed by
    at most `max_wheel_acceleration * dt` per step (Gazebo's diff-drive acceleration limit).
    """

    def __init__(self, spec: RobotSpec) -> None:
        self.spec = spec
        self.target = (0.0, 0.0)
        self.wheel_speeds = (0.0, 0.0)      # left, right [m/s]

    def set_target(self, linear: float, angular: float) -> None:
        self.target = (clamp(float(linear), self.spec.max_linear), clamp(float(angular), self.spec.max_angular))

    def stop(self) -> None:
        self.target = (0.0, 0.0)
        self.wheel_speeds = (0.0, 0.0)

    def update(self, dt: float) -> tuple[float, float]:
        """Advance the wheel speeds by one step; returns the body's (linear, angular) speed."""
        linear, angular = self.target
        half = self.spec.wheel_separation / 2.0
        step = self.spec.max_wheel_acceleration * dt
        left = _approach(self.wheel_speeds[0], linear - angular * half, step)
        right = _approach(self.wheel_speeds[1], linear + angular * half, step)
        self.wheel_speeds = (left, right)
        return ((left + right) / 2.0, (right - left) / self.spec.wheel_separation)


def integrate_twist(pose: tuple[float, float, float], twist: tuple[float, float, float],
                    dt: float) -> tuple[float, float, float]:
    """The pose after `dt` [s] of a body velocity, with no dynamics at all (a frictionless plane).

    Nav2's loopback simulator moves its robot this way: the command is the motion, applied in the
    body frame at the heading the step starts from (first order, as the loopback simulator does;
    at its 50-100 Hz the error on an arc is well under a millimetre per metre).

    Args:
        pose: (x [m], y [m], yaw [rad]).
        twist: (vx [m/s], vy [m/s], wz [rad/s]) in the body frame.
        dt: step [s].

    Returns:
        (x, y, yaw), yaw wrapped to [-pi, pi).
    """
    x, y, yaw = pose
    dx, dy, dyaw = (float(v) * dt for v in twist)
    cos, sin = math.cos(yaw), math.sin(yaw)
    return x + dx * cos - dy * sin, y + dx * sin + dy * cos, wrap_angle(yaw + dyaw)


def _approach(current: float, target: float, step: float) -> float:
    if target > current:
        return min(target, current + step)
    return max(target, current - step)


class WheelOdometry:
    """Wheel encoders and the odometry integrated from them, in the `odom` frame.

    `odom` is where the robot stood when odometry last started (spawn or reset); teleports are
    not seen, as a real robot's encoders would not see being carried.
    """

    def __init__(self, spec: RobotSpec, rng: np.random.Generator, slip_stddev: float) -> None:
        if slip_stddev < 0:
            raise ValueError(f'slip_stddev must be >= 0, got {slip_stddev}')
        self.spec = spec
        self.rng = rng
        self.slip_stddev = float(slip_stddev)
        self.reset()

    def reset(self) -> None:
        self.x = self.y = self.yaw = 0.0
        self.linear = self.angular = 0.0
        self.wheel_positions = [0.0, 0.0]     # [rad]
        self.wheel_velocities = [0.0, 0.0]    # [rad/s]

    def update(self, forward: float, turn: float, dt: float) -> None:
        """The body moved `forward` [m] along its mid-step heading and turned `turn` [rad]."""
        half = self.spec.wheel_separation / 2.0
        travel = [forward - turn * half, forward + turn * half]
        if self.slip_stddev > 0.0:
            noise = self.rng.standard_normal(2).tolist()
            k = self.slip_stddev
            travel = [t + k * math.sqrt(abs(t)) * n for t, n in zip(travel, noise)]
        r = self.spec.wheel_radius
        for i in (0, 1):
            self.wheel_positions[i] += travel[i] / r
            self.wheel_velocities[i] = travel[i] / r / dt
        ds = (travel[0] + travel[1]) / 2.0
        dyaw = (travel[1] - travel[0]) / self.spec.wheel_separation
        heading = self.yaw + dyaw / 2.0
        self.x += ds * math.cos(heading)
        self.y += ds * math.sin(heading)
        self.yaw = wrap_angle(self.yaw + dyaw)
        self.linear, self.angular = ds / dt, dyaw / dt
