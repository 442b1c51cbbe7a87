"""Robots from their model files: the numbers a model's Gazebo plugins and sensors state.

    robot = robot_from_xml(open('models/turtlebot3_burger/model.sdf').read(), fallback='burger')
    robot.spec.wheel_separation, robot.lidar.samples, robot.warning

A model file (an SDF `<model>`, or a URDF `<robot>` with `<gazebo>` tags) tells Gazebo how the
robot drives and senses; zros reads the same elements:
- the diff-drive plugin: Gazebo classic's (`libgazebo_ros_diff_drive.so`: `wheel_separation`,
  `wheel_diameter`, `max_wheel_acceleration`) or Gazebo Sim's (`gz-sim-diff-drive-system`:
  `wheel_separation`, `wheel_radius`, `max_linear_acceleration`, `max_linear_velocity`,
  `max_angular_velocity`, and where it talks: `topic`, `odom_topic`, `tf_topic`, `frame_id`,
  `child_frame_id`, `odom_publish_frequency`);
- the first lidar (`type="ray"`, `"gpu_ray"`, Gazebo Sim's `"gpu_lidar"`, `"lidar"`): `samples`,
  `min_angle`, `max_angle`, range `min`/`max`, `update_rate`, noise `stddev`, and in Gazebo Sim
  its `topic` and `gz_frame_id`; the IMU sensor's `topic` and `gz_frame_id`;
- Gazebo Sim's `gz-sim-joint-state-publisher-system`: its `topic`.
Where a Gazebo Sim model says nothing, its topics and frames are Gazebo's defaults
(zros.sim.gz_topics); `RobotModel.topics` holds them, as Gazebo topic names.
The rest of the robot (body disc, mounts, speed limits) is the robot whose wheels the Gazebo Sim
diff-drive plugin states (the TurtleBot4's Create 3 base: separation 0.233 m, radius 0.03575 m),
else the TurtleBot3 the XML names (`waffle_pi`, `waffle`, `burger`), else `fallback`
($TURTLEBOT3_MODEL). A model without a diff-drive plugin is that TurtleBot3, with a one-line
`warning`.
"""
from __future__ import annotations

from dataclasses import replace
from typing import NamedTuple

from zros.sim.robot import TURTLEBOT4, RobotSpec, robot_spec
from zros.sim.gz_topics import RobotTopics, default_topics, gz_name
from zros.sim.sdf import SdfError, XmlElement, numbers, parse_xml
from zros.sim.sensors import LDS_01, LidarSpec

__all__ = ['RobotModel', 'robot_from_xml', 'turtlebot3_named']

_DIFF_DRIVE = 'libgazebo_ros_diff_drive.so'
#: Gazebo Sim's systems, by a part of the plugin's `filename` (`gz-sim-...`, `libgz-sim8-...so`,
#: Fortress's `ignition-gazebo-...`) or its class `name`.
_GZ_DIFF_DRIVE = ('diff-drive-system', 'systems::DiffDrive')
_GZ_JOINT_STATES = ('joint-state-publisher-system', 'systems::JointStatePublisher')
_LIDARS = ('ray', 'gpu_ray', 'gpu_lidar', 'lidar')
#: Robots known by their wheels (a model file names no robot zros could look up otherwise).
_BY_WHEELS = (TURTLEBOT4,)
_WHEEL_TOLERANCE = 1e-4    # [m]


class RobotModel(NamedTuple):
    """What a model file makes of a robot: its spec, its lidar, and a warning ('' if none)."""
    spec: RobotSpec
    lidar: LidarSpec
    warning: str
    topics: RobotTopics | None = None   # Gazebo Sim's topic names and frames (None for a classic model)


def turtlebot3_named(xml: str, fallback: str) -> str:
    """The TurtleBot3 model an XML text names (waffle_pi before waffle), else `fallback`."""
    return next((m for m in ('waffle_pi', 'waffle', 'burger') if m in xml), fallback)


def robot_from_xml(xml: str, *, fallback: str, source: str = '<robot XML>', world: str = 'default') -> RobotModel:
    """The robot an SDF or URDF text describes; SdfError (one line) if the XML is malformed.
    `world` is the world it goes into (Gazebo Sim's default topic names contain it)."""
    base = robot_spec(turtlebot3_named(xml, fallback))
    root = parse_xml(xml, source)
    model = root.find('model') if root.tag == 'sdf' else root
    name = model.attrib.get('name', '?') if model is not None else root.attrib.get('name', '?')
    classic = _plugin(root, (_DIFF_DRIVE,))
    gz = _plugin(root, _GZ_DIFF_DRIVE)
    sensor = next((s for s in root.iter('sensor') if s.attrib.get('type') in _LIDARS), None)
    lidar = _lidar(sensor, source) if sensor is not None else LDS_01
    topics = _gz_topics(root, model, name, world, gz, sensor) if classic is None else None
    if gz is not None:
        base = _robot_by_wheels(gz, base, source)
        spec = replace(base,
                       wheel_separation=_number(gz, 'wheel_separation', base.wheel_separation, source),
                       wheel_radius=_number(gz, 'wheel_radius', base.wheel_radius, source),
                       max_wheel_acceleration=_number(gz, 'max_linear_acceleration', base.max_wheel_acceleration,
                                                      source),
                       max_linear=_number(gz, 'max_linear_velocity', base.max_linear, source),
                       max_angular=_number(gz, 'max_angular_velocity', base.max_angular, source))
        _check(spec, gz, 'wheel_separation, wheel_radius, max_linear_acceleration and the maximum velocities',
               source)
        return RobotModel(spec, lidar, '', topics)
    if classic is None:
        return RobotModel(base, lidar, f"model '{name}' has no diff-drive plugin ({_DIFF_DRIVE} or "
                                       f'gz-sim-diff-drive-system): simulating a TurtleBot3 {base.model}', topics)
    spec = replace(base,
                   wheel_separation=_number(classic, 'wheel_separation', base.wheel_separation, source),
                   wheel_radius=_number(classic, 'wheel_diameter', 2 * base.wheel_radius, source) / 2,
                   max_wheel_acceleration=_number(classic, 'max_wheel_acceleration', base.max_wheel_acceleration,
                                                  source))
    _check(spec, classic, 'wheel_separation, wheel_diameter and max_wheel_acceleration', source)
    return RobotModel(spec, lidar, '')


def _robot_by_wheels(plugin: XmlElement, named: RobotSpec, source: str) -> RobotSpec:
    """The known robot whose wheel separation and radius the diff-drive `plugin` states, else `named`."""
    wheels = (_number(plugin, 'wheel_separation', 0.0, source), _number(plugin, 'wheel_radius', 0.0, source))
    return next((spec for spec in _BY_WHEELS
                 if abs(spec.wheel_separation - wheels[0]) < _WHEEL_TOLERANCE
                 and abs(spec.wheel_radius - wheels[1]) < _WHEEL_TOLERANCE), named)


def _plugin(root: XmlElement, marks: tuple[str, ...]) -> XmlElement | None:
    """The first `<plugin>` whose filename or name contains one of `marks`."""
    return next((p for p in root.iter('plugin')
                 if any(mark in p.attrib.get('filename', '') or mark in p.attrib.get('name', '') for mark in marks)),
                None)


def _check(spec: RobotSpec, plugin: XmlElement, what: str, source: str) -> None:
    if not all(value > 0 for value in (spec.wheel_separation, spec.wheel_radius, spec.max_wheel_acceleration,
                                       spec.max_linear, spec.max_angular)):
        raise SdfError(f'{source}:{plugin.line}: {what} must be > 0')


def _gz_topics(root: XmlElement, model: XmlElement | None, name: str, world: str, drive: XmlElement | None,
               lidar: XmlElement | None) -> RobotTopics:
    """Gazebo Sim's topics and frames of a model: what its plugins and sensors say, else Gazebo's
    defaults (a sensor's default topic is scoped by its link and name)."""
    imu = next((s for s in root.iter('sensor') if s.attrib.get('type') == 'imu'), None)
    links = {id(s): link.attrib.get('name', '') for link in root.iter('link') for s in link.iter('sensor')}
    links.update({id(s): g.attrib['reference'] for g in root.iter('gazebo') if g.attrib.get('reference')
                  for s in g.iter('sensor')})   # a URDF's sensors sit in <gazebo reference="LINK">
    first_link = next(iter(model.findall('link')), None) if model is not None else None

    def scoped(sensor: XmlElement | None, kind: str) -> tuple[str, str]:
        return (links.get(id(sensor), 'base_link'), sensor.attrib.get('name', kind)) if sensor is not None \
            else ('base_link', kind)
    topics = default_topics(name, world, lidar=scoped(lidar, 'lidar'), imu=scoped(imu, 'imu'))
    if first_link is not None:
        topics = topics._replace(base_frame=f"{name}/{first_link.attrib.get('name', 'base_link')}")
    joints = _plugin(root, _GZ_JOINT_STATES)
    chosen = {'cmd_vel': _text(drive, 'topic'), 'odom': _text(drive, 'odom_topic'), 'tf': _text(drive, 'tf_topic'),
              'odom_frame': _text(drive, 'frame_id'), 'base_frame': _text(drive, 'child_frame_id'),
              'joint_states': _text(joints, 'topic'), 'scan': _text(lidar, 'topic'),
              'scan_frame': _text(lidar, 'gz_frame_id'), 'imu': _text(imu, 'topic'),
              'imu_frame': _text(imu, 'gz_frame_id')}
    topics = topics._replace(**{key: value for key, value in chosen.items() if value})
    topics = topics._replace(**{key: gz_name(getattr(topics, key))
                                for key in ('cmd_vel', 'odom', 'tf', 'joint_states', 'scan', 'imu')})
    return topics._replace(namespace=topics.cmd_vel.rpartition('/')[0].strip('/'))


def _text(parent: XmlElement | None, tag: str) -> str:
    """The text of `parent`'s direct child `tag` ('' if none)."""
    return parent.findtext(tag) if parent is not None else ''


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
