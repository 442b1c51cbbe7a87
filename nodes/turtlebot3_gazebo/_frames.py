"""The robot's fixed and wheel frames, as robot_state_publisher would give them from the URDF.

The simulator publishes them itself (`publish_robot_frames`, on by default) so that the TF tree
of the reference (odom -> base_footprint -> base_link -> base_scan, imu_link, wheels, caster) is
whole with the simulator alone; with robot_state_publisher running on the TurtleBot3 URDF, turn
it off.
"""
from __future__ import annotations

import math

from zros.sim import RobotSpec
from zros.sim.model_file import WHEEL_JOINTS

__all__ = ['static_frames', 'wheel_frames', 'WHEEL_JOINTS']

_WHEEL_LINKS = ('wheel_left_link', 'wheel_right_link')
_WHEEL_ROLL = -1.57        # the URDF's wheel joint rpy: the wheel axle along base_link's y


def static_frames(spec: RobotSpec) -> list[tuple[str, str, tuple[float, float, float]]]:
    """(parent, child, translation) of the fixed joints the simulated robot has (not the URDF's
    camera frames), all unrotated: the URDF's casters carry ROBOTIS's -1.57 roll, which nothing
    reads from a caster frame, so the simulator leaves it out."""
    frames = [('base_footprint', 'base_link', (0.0, 0.0, spec.base_height)),
              ('base_link', 'base_scan', spec.lidar_mount),
              ('base_link', 'imu_link', spec.imu_mount)]
    if len(spec.caster_mounts) == 1:
        frames.append(('base_link', 'caster_back_link', spec.caster_mounts[0]))
    else:
        frames += [('base_link', f'caster_back_{side}_link', mount)
                   for side, mount in zip(('right', 'left'), spec.caster_mounts)]
    return frames


def wheel_frames(spec: RobotSpec, positions: tuple[float, float]
                 ) -> list[tuple[str, str, tuple[float, float, float], tuple[float, float, float, float]]]:
    """(parent, child, translation, rotation xyzw) of both wheels at joint angles `positions` [rad]:
    the joint's fixed roll, then the wheel's turn about its axle."""
    sr, cr = math.sin(_WHEEL_ROLL / 2.0), math.cos(_WHEEL_ROLL / 2.0)
    frames = []
    for link, mount, angle in zip(_WHEEL_LINKS, spec.wheel_mounts, positions):
        sa, ca = math.sin(angle / 2.0), math.cos(angle / 2.0)
        frames.append(('base_link', link, mount, (sr * ca, -sr * sa, cr * sa, cr * ca)))
    return frames
