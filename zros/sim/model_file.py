"""Robots from their model files: the numbers a model's Gazebo plugins and sensors state.

    robot = robot_from_xml(open('models/turtlebot3_burger/model.sdf').read(), fallback='burger')
    robot.spec.wheel_separation, robot.lidar.samples, robot.warning

A model file (an SDF `<model>`, or a URDF `<robot>` with `<gazebo>` tags) tells Gazebo how the
robot drives and senses; zros reads the same elements:
- the diff-drive plugin (`libgazebo_ros_diff_drive.so`): `wheel_separation`, `wheel_diameter`,
  `max_wheel_acceleration`;
- the first ray sensor (`type="ray"` or `"gpu_ray"`): `samples`, `min_angle`, `max_angle`,
  range `min`/`max`, `update_rate`, noise `stddev`.
The rest of the robot (body disc, mounts, speed limits) is the TurtleBot3 the XML names
(`waffle_pi`, `waffle`, `burger`), else `fallback` ($TURTLEBOT3_MODEL). A model without a
diff-drive plugin is that TurtleBot3, with a one-line `warning`.
"""
from __future__ import annotations

from dataclasses import replace
from typing import NamedTuple

from zros.sim.robot import RobotSpec, robot_spec
from zros.sim.sdf import SdfError, XmlElement, numbers, parse_xml
from zros.sim.sensors import LDS_01, LidarSpec

__all__ = ['RobotModel', 'robot_from_xml', 'turtlebot3_named']

_DIFF_DRIVE = 'libgazebo_ros_diff_drive.so'


class RobotModel(NamedTuple):
    """What a model file makes of a robot: its spec, its lidar, and a warning ('' if none)."""
    spec: RobotSpec
    lidar: LidarSpec
    warning: str


def turtlebot3_named(xml: str, fallback: str) -> str:
    """The TurtleBot3 model an XML text names (waffle_pi before waffle), else `fallback`."""
    return next((m for m in ('waffle_pi', 'waffle', 'burger') if m in xml), fallback)


def robot_from_xml(xml: str, *, fallback: str, source: str = '<robot XML>') -> RobotModel:
    """The robot an SDF or URDF text describes; SdfError (one line) if the XML is malformed."""
    base = robot_spec(turtlebot3_named(xml, fallback))
    root = parse_xml(xml, source)
    plugin = next((p for p in root.iter('plugin') if p.attrib.get('filename', '').endswith(_DIFF_DRIVE)), None)
    sensor = next((s for s in root.iter('sensor') if s.attrib.get('type') in ('ray', 'gpu_ray')), None)
    lidar = _lidar(sensor, source) if sensor is not None else LDS_01
    if plugin is None:
        name = root.find('model').attrib.get('name', '?') if root.find('model') is not None else root.attrib.get('name', '?')
        return RobotModel(base, lidar, f"model '{name}' has no {_DIFF_DRIVE} plugin: simulating a TurtleBot3 "
                                       f'{base.model}')
    spec = replace(base,
                   wheel_separation=_number(plugin, 'wheel_separation', base.wheel_separation, source),
                   wheel_radius=_number(plugin, 'wheel_diameter', 2 * base.wheel_radius, source) / 2,
                   max_wheel_acceleration=_number(plugin, 'max_wheel_acceleration', base.max_wheel_acceleration,
                                                  source))
    if not (spec.wheel_separation > 0 and spec.wheel_radius > 0 and spec.max_wheel_acceleration > 0):
        raise SdfError(f'{source}:{plugin.line}: wheel_separation, wheel_diameter and max_wheel_acceleration '
                       'must be > 0')
    return RobotModel(spec, lidar, '')


def _number(parent: XmlElement, tag: str, default: float, source: str) -> float:
    element = next(parent.iter(tag), None)
    return numbers(element, 1, source)[0] if element is not None else default


def _lidar(sensor: XmlElement, source: str) -> LidarSpec:
    """A ray sensor's scan (its horizontal fan) as a LidarSpec; missing values are the LDS-01's."""
    lidar = LidarSpec(samples=int(_number(sensor, 'samples', LDS_01.samples, source)),
                      angle_min=_number(sensor, 'min_angle', LDS_01.angle_min, source),
                      angle_max=_number(sensor, 'max_angle', LDS_01.angle_max, source),
                      range_min=_number(sensor, 'min', LDS_01.range_min, source),
                      range_max=_number(sensor, 'max', LDS_01.range_max, source),
                      noise_stddev=_number(sensor, 'stddev', LDS_01.noise_stddev, source),
                      rate=_number(sensor, 'update_rate', LDS_01.rate, source))
    if lidar.samples < 2 or not lidar.angle_max > lidar.angle_min or not 0 <= lidar.range_min < lidar.range_max:
        raise SdfError(f'{source}:{sensor.line}: ray sensor needs samples >= 2, max_angle > min_angle and '
                       '0 <= range min < max')
    return lidar
