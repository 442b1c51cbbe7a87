"""The TurtleBot3's simulated sensors: the LDS-01 lidar and the IMU, as Gazebo models them.

Lidar (Gazebo model.sdf): 360 samples from 0 to 6.28 rad (so the increment is 6.28 / 359, as
Gazebo emits, not exactly 1 degree), 0.12-3.5 m, 5 Hz, Gaussian noise with sigma 0.01 m. A beam
that meets nothing within range reads +inf; one whose first obstacle is closer than `range_min`
reads -inf (REP 117's "too close"), and is blocked there, unlike Gazebo Classic, whose rays start
at `range_min` and so see through anything nearer.

IMU (Gazebo model.sdf): 200 Hz, gyro noise sigma 2e-4 rad/s, accelerometer noise sigma
1.7e-2 m/s^2; orientation is the true one (Gazebo's IMU reports its world orientation).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from zros.sim.raycast import cast_fan

__all__ = ['LidarSpec', 'LDS_01', 'RPLIDAR_A1', 'ImuSpec', 'TURTLEBOT3_IMU', 'ImuReading', 'scan_ranges', 'GRAVITY']

GRAVITY = 9.80665


@dataclass(frozen=True)
class LidarSpec:
    """A planar lidar: angles [rad] counter-clockwise from the sensor's +x, ranges [m]."""
    samples: int = 360
    angle_min: float = 0.0
    angle_max: float = 6.28
    range_min: float = 0.12
    range_max: float = 3.5
    noise_stddev: float = 0.01
    rate: float = 5.0                  # [Hz]

    @property
    def angle_increment(self) -> float:
        return (self.angle_max - self.angle_min) / (self.samples - 1)

    def angles(self) -> np.ndarray:
        """(samples,) beam angles [rad] in the sensor frame."""
        return self.angle_min + self.angle_increment * np.arange(self.samples)


LDS_01 = LidarSpec()

#: The TurtleBot4's RPLIDAR A1 as its Gazebo Sim model states it: 360 samples over 0-6.28 rad,
#: 0.164-20 m, 10 Hz (the model gives no noise; zros.sim.model_file then keeps the LDS-01's).
RPLIDAR_A1 = LidarSpec(samples=360, angle_min=0.0, angle_max=6.28, range_min=0.164, range_max=20.0, rate=10.0)


@dataclass(frozen=True)
class ImuSpec:
    rate: float = 200.0                # [Hz]
    gyro_noise_stddev: float = 2e-4    # [rad/s]
    accel_noise_stddev: float = 1.7e-2 # [m/s^2]


TURTLEBOT3_IMU = ImuSpec()


class ImuReading(NamedTuple):
    """orientation: yaw [rad]; angular_velocity: (x, y, z) [rad/s]; linear_acceleration: (x, y, z)
    [m/s^2], in imu_link (aligned with base_link), gravity's reaction on +z."""
    yaw: float
    angular_velocity: tuple[float, float, float]
    linear_acceleration: tuple[float, float, float]


def scan_ranges(spec: LidarSpec, sensor_pose: tuple[float, float, float], edges: np.ndarray,
                circles: np.ndarray, rng: np.random.Generator | None) -> np.ndarray:
    """One scan from a sensor at (x, y, yaw) [m, rad]: (samples,) float32 ranges, with noise
    from `rng` (none if `rng` is None), +inf for no return and -inf for too close."""
    x, y, yaw = sensor_pose
    true = cast_fan((x, y), yaw + spec.angle_min, spec.angle_increment, spec.samples, edges, circles,
                    spec.range_max)
    ranges = true.copy()
    valid = np.isfinite(true)
    if rng is not None and spec.noise_stddev > 0.0:
        noisy = true[valid] + rng.standard_normal(int(valid.sum())) * spec.noise_stddev
        ranges[valid] = np.clip(noisy, spec.range_min, spec.range_max)
    ranges[valid & (true < spec.range_min)] = -math.inf
    return ranges.astype(np.float32)
