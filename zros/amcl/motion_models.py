"""Odometry motion models: move every particle by the odometry's motion, with noise.

Both are nav2_amcl's (Probabilistic Robotics, table 5.6 "sample_motion_model_odometry", with
Nav2's handling of driving backwards), vectorised over the particles:

- `DifferentialMotionModel` (`nav2_amcl::DifferentialMotionModel`, alias `differential`):
  the motion between two odometry poses is a rotation, a straight line, a rotation; each is
  perturbed with a Gaussian whose variance grows with the motion: alpha1 rotation from
  rotation, alpha2 rotation from translation, alpha3 translation from translation, alpha4
  translation from rotation.
- `OmniMotionModel` (`nav2_amcl::OmniMotionModel`, alias `omnidirectional`): a translation,
  a strafe and a rotation, alpha5 being the strafe noise from translation.

Poses are (N, 3) arrays x, y [m], yaw [rad, counter-clockwise]; odometry poses are (3,).
"""
from __future__ import annotations

import math
from typing import Callable

import numpy as np

from zros.rotations import angle_diff, wrap_angle

__all__ = ['MotionModel', 'DifferentialMotionModel', 'OmniMotionModel', 'create_motion_model', 'MOTION_MODELS']


class MotionModel:
    """Moves particles by an odometry increment. `alphas` are alpha1..alpha5 (Nav2's names)."""

    def __init__(self, alpha1: float, alpha2: float, alpha3: float, alpha4: float, alpha5: float = 0.0) -> None:
        self.alpha1, self.alpha2, self.alpha3, self.alpha4, self.alpha5 = alpha1, alpha2, alpha3, alpha4, alpha5

    def odometry_update(self, particles: np.ndarray, pose: np.ndarray, delta: np.ndarray,
                        rng: np.random.Generator) -> None:
        """Move `particles` (N, 3) in place by the motion `delta` (dx, dy, dyaw in the odom frame)
        that ended at odometry `pose`."""
        raise NotImplementedError


class DifferentialMotionModel(MotionModel):

    def odometry_update(self, particles: np.ndarray, pose: np.ndarray, delta: np.ndarray,
                        rng: np.random.Generator) -> None:
        old_yaw = pose[2] - delta[2]
        trans = math.hypot(delta[0], delta[1])
        # Below 1 cm the heading of the motion is noise: treat it as a turn in place.
        rot1 = 0.0 if trans < 0.01 else angle_diff(math.atan2(delta[1], delta[0]), old_yaw)
        rot2 = angle_diff(delta[2], rot1)
        # Driving backwards is a half turn, a line and a half turn; its noise must not be.
        rot1_noise = min(abs(angle_diff(rot1, 0.0)), abs(angle_diff(rot1, math.pi)))
        rot2_noise = min(abs(angle_diff(rot2, 0.0)), abs(angle_diff(rot2, math.pi)))
        a1, a2, a3, a4 = self.alpha1, self.alpha2, self.alpha3, self.alpha4
        n = len(particles)
        rot1_hat = rot1 - math.sqrt(a1 * rot1_noise ** 2 + a2 * trans ** 2) * rng.standard_normal(n)
        trans_hat = trans - math.sqrt(a3 * trans ** 2 + a4 * rot1_noise ** 2 + a4 * rot2_noise ** 2) \
            * rng.standard_normal(n)
        rot2_hat = rot2 - math.sqrt(a1 * rot2_noise ** 2 + a2 * trans ** 2) * rng.standard_normal(n)
        heading = particles[:, 2] + rot1_hat
        particles[:, 0] += trans_hat * np.cos(heading)
        particles[:, 1] += trans_hat * np.sin(heading)
        particles[:, 2] = wrap_angle(heading + rot2_hat)


class OmniMotionModel(MotionModel):

    def odometry_update(self, particles: np.ndarray, pose: np.ndarray, delta: np.ndarray,
                        rng: np.random.Generator) -> None:
        old_yaw = pose[2] - delta[2]
        trans = math.hypot(delta[0], delta[1])
        rot = delta[2]
        a1, a2, a3, a4, a5 = self.alpha1, self.alpha2, self.alpha3, self.alpha4, self.alpha5
        n = len(particles)
        trans_hat = trans + math.sqrt(a3 * trans ** 2 + a1 * rot ** 2) * rng.standard_normal(n)
        rot_hat = rot + math.sqrt(a4 * trans ** 2 + a2 * rot ** 2) * rng.standard_normal(n)
        strafe_hat = math.sqrt(a1 * rot ** 2 + a5 * trans ** 2) * rng.standard_normal(n)
        bearing = angle_diff(math.atan2(delta[1], delta[0]), old_yaw) + particles[:, 2]
        cos_b, sin_b = np.cos(bearing), np.sin(bearing)
        particles[:, 0] += trans_hat * cos_b + strafe_hat * sin_b
        particles[:, 1] += trans_hat * sin_b - strafe_hat * cos_b
        particles[:, 2] = wrap_angle(particles[:, 2] + rot_hat)


#: `robot_model_type` values: Nav2's plugin names and the pre-Humble aliases ROBOTIS files used.
MOTION_MODELS: dict[str, Callable[..., MotionModel]] = {
    'nav2_amcl::DifferentialMotionModel': DifferentialMotionModel,
    'differential': DifferentialMotionModel,
    'nav2_amcl::OmniMotionModel': OmniMotionModel,
    'omnidirectional': OmniMotionModel,
}


def create_motion_model(robot_model_type: str, alphas: tuple[float, float, float, float, float]) -> MotionModel:
    """The motion model named by `robot_model_type`; ValueError naming the known ones."""
    try:
        factory = MOTION_MODELS[robot_model_type]
    except KeyError:
        raise ValueError(f"unknown robot_model_type '{robot_model_type}' "
                         f"(known: {', '.join(MOTION_MODELS)})") from None
    return factory(*alphas)
