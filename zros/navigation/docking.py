"""opennav_docking's geometry as plain code: dock databases, staging poses, the graceful control
law that drives the robot onto a dock, and the "docked" test of simple_charging_dock.

Nav2 Jazzy's docking_server (`nodes/opennav_docking/opennav_docking.py` wraps this module)
docks in three moves: reach the dock's staging pose (a point `staging_x_offset` in front of the
dock, usually negative: behind it along the dock's heading), then drive onto the dock with a
smooth control law (Park & Kuipers' egocentric polar law, nav2_graceful_controller's) aimed a
little past the dock pose, until the robot is within `docking_threshold` of it. Undocking drives
back to the staging pose computed from where the robot sits. Poses here are (x, y, yaw) tuples in
one frame; the node does the TF.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, fields
from pathlib import Path
from typing import Any

from zros.rotations import wrap_angle

__all__ = ['Dock', 'DockDatabaseError', 'ControlLaw', 'load_dock_database', 'parse_docks', 'staging_pose',
           'approach_target', 'to_robot_frame', 'is_within']

Pose2D = tuple[float, float, float]

# The dock pose the controller aims at is moved this far past the dock along its heading, so the
# law keeps driving until contact instead of slowing to nothing at the dock pose.
APPROACH_PROJECTION_M = 0.25


class DockDatabaseError(ValueError):
    """A dock database (YAML file or `docks` parameters) that cannot be used; a one-line reason."""


@dataclass(frozen=True)
class Dock:
    """One dock instance: its name, type (a dock plugin's name), frame, pose and optional id."""
    name: str
    type: str
    frame: str
    pose: Pose2D
    id: str = ''


def parse_docks(entries: dict[str, dict], source: str, default_frame: str = 'map') -> dict[str, Dock]:
    """Docks from a mapping name -> {type, pose: [x, y, yaw], frame?, id?} (a database file's
    `docks:` or the node's `<dock>.*` parameters); `source` names it in errors."""
    docks = {}
    for name, attribs in entries.items():
        if not isinstance(attribs, dict) or not attribs.get('type'):
            raise DockDatabaseError(f'Dock {name} in {source} has no dock "type"')
        pose = attribs.get('pose')
        if not isinstance(pose, (list, tuple)) or len(pose) != 3:
            raise DockDatabaseError(f'Dock {name} in {source} has no valid "pose" (want [x, y, yaw])')
        try:
            xyz = tuple(float(v) for v in pose)
        except (TypeError, ValueError):
            raise DockDatabaseError(f'Dock {name} in {source}: pose {pose} is not three numbers') from None
        docks[str(name)] = Dock(str(name), str(attribs['type']), str(attribs.get('frame') or default_frame),
                                xyz, str(attribs.get('id', '')))  # type: ignore[arg-type]
    return docks


def load_dock_database(path: str | Path) -> dict[str, Dock]:
    """The docks of a YAML dock database file (`docks: {name: {type, frame, pose, id}}`)."""
    import yaml
    try:
        data = yaml.safe_load(Path(path).read_text())
    except OSError as exc:
        raise DockDatabaseError(f'Cannot read the dock database {path}: {exc.strerror or exc}') from None
    except yaml.YAMLError as exc:
        raise DockDatabaseError(f'Dock database {path} is not YAML: {str(exc).splitlines()[0]}') from None
    if not isinstance(data, dict) or not isinstance(data.get('docks'), dict):
        raise DockDatabaseError(f"Dock database ({path}) does not contain 'docks'.")
    return parse_docks(data['docks'], str(path))


def staging_pose(dock: Pose2D, x_offset: float = -0.7, yaw_offset: float = 0.0) -> Pose2D:
    """simple_charging_dock's staging pose: `x_offset` along the dock's heading (negative: in front
    of a dock the robot drives into forwards), heading turned by `yaw_offset`."""
    x, y, yaw = dock
    return x + math.cos(yaw) * x_offset, y + math.sin(yaw) * x_offset, wrap_angle(yaw + yaw_offset)


def approach_target(dock: Pose2D, projection: float = APPROACH_PROJECTION_M) -> Pose2D:
    """Where the controller aims while docking: the dock pose pushed `projection` further along
    its heading."""
    x, y, yaw = dock
    return x + math.cos(yaw) * projection, y + math.sin(yaw) * projection, yaw


def to_robot_frame(robot: Pose2D, target: Pose2D) -> Pose2D:
    """`target` (same frame as `robot`) seen from the robot: x ahead, y to the left."""
    dx, dy = target[0] - robot[0], target[1] - robot[1]
    c, s = math.cos(robot[2]), math.sin(robot[2])
    return c * dx + s * dy, -s * dx + c * dy, wrap_angle(target[2] - robot[2])


def is_within(robot: Pose2D, target: Pose2D, linear: float, angular: float | None = None) -> bool:
    """The robot is within `linear` [m] of `target` (and `angular` [rad] of its heading, if given)."""
    if math.hypot(robot[0] - target[0], robot[1] - target[1]) >= linear:
        return False
    return angular is None or abs(wrap_angle(target[2] - robot[2])) < angular


@dataclass
class ControlLaw:
    """opennav_docking's `controller.*` parameters (Nav2's names and defaults) and the smooth
    control law they configure."""
    k_phi: float = 3.0
    k_delta: float = 2.0
    beta: float = 0.4
    lambda_: float = 2.0
    v_linear_min: float = 0.1
    v_linear_max: float = 0.25
    v_angular_max: float = 0.75
    slowdown_radius: float = 0.25

    @staticmethod
    def param_name(field_name: str) -> str:
        """The Nav2 parameter name of a field (`lambda` is a Python keyword)."""
        return field_name.rstrip('_')

    @classmethod
    def names(cls) -> list[str]:
        return [f.name for f in fields(cls)]

    def curvature(self, r: float, phi: float, delta: float) -> float:
        """The law's path curvature for egocentric polar coordinates (r, phi, delta)."""
        proportional = self.k_delta * (delta - math.atan(-self.k_phi * phi))
        feedback = (1.0 + self.k_phi / (1.0 + (self.k_phi * phi) ** 2)) * math.sin(delta)
        return -(proportional + feedback) / r

    def velocity(self, target: Pose2D, backward: bool = False) -> tuple[float, float]:
        """(v, w) towards `target` given in the robot's frame: slower on tight curves and within
        `slowdown_radius`, within the speed limits; reversed when driving `backward`."""
        x, y, yaw = target
        r = math.hypot(x, y)
        if r < 1e-9:
            return 0.0, 0.0
        line_of_sight = math.atan2(-y, x) + (math.pi if backward else 0.0)
        phi = wrap_angle(yaw + line_of_sight)
        delta = wrap_angle(line_of_sight)
        curvature = self.curvature(r, phi, delta)
        if backward:
            curvature = -curvature
        v = self.v_linear_max / (1.0 + self.beta * abs(curvature) ** self.lambda_)
        v = min(self.v_linear_max * r / self.slowdown_radius, v)
        v = min(max(v, self.v_linear_min), self.v_linear_max)
        if backward:
            v = -v
        w = max(-self.v_angular_max, min(self.v_angular_max, curvature * v))
        if curvature != 0.0:
            v = w / curvature
        return v, w

    @classmethod
    def from_params(cls, get: Any) -> ControlLaw:
        """Built with `get(name, default)` (e.g. Nav2Params.get) for each `controller.<name>`."""
        law = cls()
        for name in cls.names():
            setattr(law, name, get(f'controller.{cls.param_name(name)}', getattr(law, name)))
        return law
