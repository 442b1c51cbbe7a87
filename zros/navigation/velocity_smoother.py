"""Velocity smoothing: nav2_velocity_smoother's limits on the controller's commands, as plain numpy.

Between the controller (`cmd_vel_nav`) and the robot (`cmd_vel`) Nav2 runs a velocity smoother:
every 1 / `smoothing_frequency` s it moves the velocity it last sent (open loop) or the measured
one (closed loop, odometry averaged over `odom_duration`) towards the latest command, no faster
than the acceleration limits allow. A velocity is the 3-vector (vx [m/s], vy [m/s], wz [rad/s]),
Twist's linear.x, linear.y and angular.z.

Per axis, a change that makes the speed larger in the same direction is limited by `max_accel`,
any other (slowing down, or passing through zero) by `max_decel` (negative) [m/s², rad/s²]. With
`scale_velocities` every axis is scaled by the one factor of the most limited axis, so the robot
keeps the commanded direction (the ratio of vx to wz) while it accelerates. Commands are first
clamped to [`min_velocity`, `max_velocity`]; a result smaller than `deadband_velocity` is zero.

Reference: navigation2 nav2_velocity_smoother (velocity_smoother.cpp: applyConstraints,
findEtaConstraint, smootherTimer) and its configuration guide.
"""
from __future__ import annotations

from dataclasses import dataclass, field, fields

import numpy as np

__all__ = ['VelocitySmootherParams', 'VelocitySmoother', 'twist_vector']

_AXES = 3


def _triple(*values: float) -> list[float]:
    return field(default_factory=lambda: list(values))


@dataclass
class VelocitySmootherParams:
    """Nav2's velocity_smoother parameters (names and defaults as its configuration guide).
    Per-axis lists are [vx, vy, wz]."""

    smoothing_frequency: float = 20.0                           # [Hz]
    scale_velocities: bool = False
    feedback: str = 'OPEN_LOOP'                                 # or 'CLOSED_LOOP'
    max_velocity: list[float] = _triple(0.5, 0.0, 2.5)          # [m/s, m/s, rad/s]
    min_velocity: list[float] = _triple(-0.5, 0.0, -2.5)        # [m/s, m/s, rad/s]
    max_accel: list[float] = _triple(2.5, 0.0, 3.2)             # [m/s², m/s², rad/s²], >= 0
    max_decel: list[float] = _triple(-2.5, 0.0, -3.2)           # [m/s², m/s², rad/s²], <= 0
    deadband_velocity: list[float] = _triple(0.0, 0.0, 0.0)     # [m/s, m/s, rad/s]
    velocity_timeout: float = 1.0                               # [s] no command for this long: stop
    odom_topic: str = 'odom'
    odom_duration: float = 0.1                                  # [s] odometry averaged over (CLOSED_LOOP)

    @classmethod
    def names(cls) -> list[str]:
        return [f.name for f in fields(cls)]

    def validate(self) -> None:
        """Raise ValueError naming the first bad parameter (Nav2 refuses to configure then)."""
        for name in ('max_velocity', 'min_velocity', 'max_accel', 'max_decel', 'deadband_velocity'):
            if len(getattr(self, name)) != _AXES:
                raise ValueError(f'{name} must have 3 values (vx, vy, wz), not {len(getattr(self, name))}')
        if any(a < 0.0 for a in self.max_accel) or any(d > 0.0 for d in self.max_decel):
            raise ValueError('Positive values set of deceleration! These should be negative to slow down! '
                             '(max_accel must be >= 0, max_decel <= 0)')
        if self.feedback not in ('OPEN_LOOP', 'CLOSED_LOOP'):
            raise ValueError(f'feedback must be OPEN_LOOP or CLOSED_LOOP, not {self.feedback!r}')
        if self.smoothing_frequency <= 0.0:
            raise ValueError(f'smoothing_frequency must be positive, not {self.smoothing_frequency}')


def twist_vector(twist: object) -> np.ndarray:
    """(3,) [vx, vy, wz] of a geometry_msgs/Twist."""
    return np.array([twist.linear.x, twist.linear.y, twist.angular.z], np.float64)


class VelocitySmoother:
    """The smoother's state: the latest command, when it came, and the velocity last sent.

    `command(v, now)` records a command; `step(now, measured)` is one smoothing period and
    returns the (3,) velocity to publish, or None when there is nothing to send (no command
    yet, or the input timed out and a zero has been sent). Single-threaded: the node calls it
    from its timer and subscription under one lock.
    """

    def __init__(self, params: VelocitySmootherParams) -> None:
        params.validate()
        self.params = params
        self._max_v = np.asarray(params.max_velocity, np.float64)
        self._min_v = np.asarray(params.min_velocity, np.float64)
        self._accel = np.asarray(params.max_accel, np.float64)
        self._decel = np.asarray(params.max_decel, np.float64)
        self._deadband = np.asarray(params.deadband_velocity, np.float64)
        self._command: np.ndarray | None = None
        self._command_time = 0.0
        self.last = np.zeros(_AXES)
        self._stopped = True

    def command(self, velocity: np.ndarray, now: float) -> bool:
        """Record a command [vx, vy, wz] received at `now` [s]; a non-finite one is refused (False)."""
        velocity = np.asarray(velocity, np.float64)
        if not np.all(np.isfinite(velocity)):
            return False
        self._command, self._command_time = velocity, now
        return True

    def reset(self) -> None:
        """Forget the command and the velocity sent (on deactivation)."""
        self._command = None
        self.last = np.zeros(_AXES)
        self._stopped = True

    def step(self, now: float, measured: np.ndarray | None = None) -> np.ndarray | None:
        """One period at `now` [s]. `measured` is the robot's velocity for CLOSED_LOOP (the last
        output is used when it is None, or in OPEN_LOOP)."""
        if self._command is None:
            return None
        target = self._command
        if now - self._command_time > self.params.velocity_timeout:
            if self._stopped or not self.last.any():
                self._stopped = True
                return None
            target = np.zeros(_AXES)
        self._stopped = False
        current = self.last
        if self.params.feedback == 'CLOSED_LOOP' and measured is not None:
            current = np.asarray(measured, np.float64)
        out = self.limit(current, target)
        self.last = out
        return out

    def limit(self, current: np.ndarray, command: np.ndarray) -> np.ndarray:
        """The velocity one period after `current` towards `command`, within every limit."""
        command = np.clip(command, self._min_v, self._max_v)
        dv = command - current
        accelerating = (np.abs(command) >= np.abs(current)) & (current * command >= 0.0)
        dv_max = np.where(accelerating, self._accel, -self._decel) / self.params.smoothing_frequency  # [per period]
        eta = 1.0
        if self.params.scale_velocities:
            eta = _common_scale(dv, dv_max)
        out = current + np.clip(eta * dv, -dv_max, dv_max)
        out[np.abs(out) < self._deadband] = 0.0
        return out


def _common_scale(dv: np.ndarray, dv_max: np.ndarray) -> float:
    """The factor every axis's change is scaled by so that the most limited axis meets its limit
    (Nav2's findEtaConstraint over the axes: the factor furthest from 1 wins)."""
    limited = np.abs(dv) > dv_max
    if not limited.any():
        return 1.0
    return float(np.min(dv_max[limited] / np.abs(dv[limited])))
