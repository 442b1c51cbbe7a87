"""Robots from their model files: what a model's Gazebo plugins and sensors say it does.

    robot = robot_from_xml(open('models/turtlebot3_burger/model.sdf').read(), fallback='burger')
    robot.spec.wheel_separation, robot.lidar.samples, robot.drive.odometry_source, robot.warning

A model file (an SDF `<model>`, or a URDF `<robot>` with `<gazebo>` tags) tells Gazebo how the
robot drives, senses and what it publishes; zros reads the same elements, with the defaults of
Gazebo's plugins (gazebo_plugins, ROS 2) where an element is absent:
- the diff-drive plugin (`libgazebo_ros_diff_drive.so`): `wheel_separation`, `wheel_diameter`,
  `max_wheel_acceleration`, `update_rate` (100), `odometry_source` (1 = WORLD, the default, or
  0 = ENCODER), `publish_odom`, `publish_odom_tf`, `publish_wheel_tf` (all false),
  `odometry_frame` (odom), `robot_base_frame` (base_footprint), and `<ros>` remappings of its
  `cmd_vel` and `odom` topics;
- the first ray sensor (`type="ray"` or `"gpu_ray"`): `samples`, `min_angle`, `max_angle`,
  range `min`/`max`, `update_rate`, noise `stddev`, and its plugin's `frame_name` (default: the
  sensor's link) and `~/out` remapping (default: `<plugin name>/out`, as Gazebo's node names it);
- the first IMU sensor: `update_rate`, the gyro's and accelerometer's noise `stddev`, frame and
  topic as for the ray sensor;
- the joint state publisher (`libgazebo_ros_joint_state_publisher.so`): `update_rate` and the
  `joint_name`s, on `joint_states`.
A sensor or publisher the file lacks is not published (Gazebo publishes only what its plugins
say). The rest of the robot (body disc, mounts, speed limits) is the TurtleBot3 the XML names
(`waffle_pi`, `waffle`, `burger`), else `fallback` ($TURTLEBOT3_MODEL). A model without a
diff-drive plugin is that TurtleBot3 as ROBOTIS's model file describes it, with a one-line
`warning`.
"""
from __future__ import annotations

from dataclasses import dataclass, replace
from typing import NamedTuple

from zros.sim.robot import RobotSpec, odometry_source, robot_spec
from zros.sim.sdf import SdfError, XmlElement, flag, numbers, parse_xml
from zros.sim.sensors import LDS_01, TURTLEBOT3_IMU, ImuSpec, LidarSpec

__all__ = ['RobotModel', 'DiffDrivePlugin', 'SensorOutput', 'JointStateOutput', 'robot_from_xml',
           'turtlebot3_named', 'turtlebot3_model', 'TURTLEBOT3_DRIVE', 'TURTLEBOT3_SCAN', 'TURTLEBOT3_IMU_OUTPUT',
           'TURTLEBOT3_JOINT_STATES', 'WHEEL_JOINTS']

_DIFF_DRIVE = 'libgazebo_ros_diff_drive.so'
_JOINT_STATES = 'libgazebo_ros_joint_state_publisher.so'
WHEEL_JOINTS = ('wheel_left_joint', 'wheel_right_joint')
#: [Hz] Gazebo's "0: as fast as possible" is one output per physics step of zros.sim (5 ms).
_EVERY_STEP = 200.0


@dataclass(frozen=True)
class DiffDrivePlugin:
    """The diff-drive plugin's outputs; the defaults are the plugin's own (gazebo_plugins, ROS 2)."""
    odometry_source: str = 'world'
    publish_odom: bool = False
    publish_odom_tf: bool = False
    publish_wheel_tf: bool = False
    odometry_frame: str = 'odom'
    robot_base_frame: str = 'base_footprint'
    update_rate: float = 100.0         # [Hz] odom, its TF and wheel TF
    cmd_vel_topic: str = 'cmd_vel'
    odom_topic: str = 'odom'


@dataclass(frozen=True)
class SensorOutput:
    """Where and how often a sensor plugin publishes: a topic relative to the robot's namespace."""
    topic: str
    frame: str
    rate: float                        # [Hz]


@dataclass(frozen=True)
class JointStateOutput:
    topic: str
    rate: float                        # [Hz]
    joints: tuple[str, ...]


#: ROBOTIS's TurtleBot3 model.sdf (turtlebot3_gazebo, humble): what its plugins publish.
TURTLEBOT3_DRIVE = DiffDrivePlugin(publish_odom=True, publish_odom_tf=True, update_rate=30.0)
TURTLEBOT3_SCAN = SensorOutput('scan', 'base_scan', LDS_01.rate)
TURTLEBOT3_IMU_OUTPUT = SensorOutput('imu', 'imu_link', TURTLEBOT3_IMU.rate)
TURTLEBOT3_JOINT_STATES = JointStateOutput('joint_states', 30.0, WHEEL_JOINTS)


class RobotModel(NamedTuple):
    """What a model file makes of a robot: its spec and sensors, what it publishes (None: not
    published), and a warning ('' if none)."""
    spec: RobotSpec
    lidar: LidarSpec
    warning: str
    drive: DiffDrivePlugin = TURTLEBOT3_DRIVE
    scan: SensorOutput | None = TURTLEBOT3_SCAN
    imu: ImuSpec | None = TURTLEBOT3_IMU
    imu_output: SensorOutput | None = TURTLEBOT3_IMU_OUTPUT
    joint_states: JointStateOutput | None = TURTLEBOT3_JOINT_STATES


def turtlebot3_named(xml: str, fallback: str) -> str:
    """The TurtleBot3 model an XML text names (waffle_pi before waffle), else `fallback`."""
    return next((m for m in ('waffle_pi', 'waffle', 'burger') if m in xml), fallback)


def turtlebot3_model(model: str) -> RobotModel:
    """A TurtleBot3 as ROBOTIS's model.sdf describes it (no file needed); ValueError if unknown."""
    return RobotModel(robot_spec(model), LDS_01, '')


def robot_from_xml(xml: str, *, fallback: str, source: str = '<robot XML>') -> RobotModel:
    """The robot an SDF or URDF text describes; SdfError (one line) if the XML is malformed."""
    base = robot_spec(turtlebot3_named(xml, fallback))
    root = parse_xml(xml, source)
    plugin = _plugin(root, _DIFF_DRIVE)
    if plugin is None:
        name = root.find('model').attrib.get('name', '?') if root.find('model') is not None else root.attrib.get('name', '?')
        return turtlebot3_model(base.model)._replace(
            warning=f"model '{name}' has no {_DIFF_DRIVE} plugin: simulating a TurtleBot3 {base.model}")
    spec = replace(base,
                   wheel_separation=_number(plugin, 'wheel_separation', base.wheel_separation, source),
                   wheel_radius=_number(plugin, 'wheel_diameter', 2 * base.wheel_radius, source) / 2,
                   max_wheel_acceleration=_number(plugin, 'max_wheel_acceleration', base.max_wheel_acceleration,
                                                  source))
    if not (spec.wheel_separation > 0 and spec.wheel_radius > 0 and spec.max_wheel_acceleration > 0):
        raise SdfError(f'{source}:{plugin.line}: wheel_separation, wheel_diameter and max_wheel_acceleration '
                       'must be > 0')
    ray = _sensor(root, ('ray', 'gpu_ray'))
    imu = _sensor(root, ('imu',))
    joint_states = _plugin(root, _JOINT_STATES)
    return RobotModel(
        spec, _lidar(ray[1], source) if ray else LDS_01, '', _drive(plugin, source),
        scan=_output(*ray, source) if ray else None,
        imu=_imu(imu[1], source) if imu else None,
        imu_output=_output(*imu, source) if imu else None,
        joint_states=None if joint_states is None else JointStateOutput(
            _remapped(joint_states, 'joint_states', '~/out') or 'joint_states',
            _rate(joint_states, 100.0, source),
            tuple(e.text.strip() for e in joint_states.iter('joint_name')) or WHEEL_JOINTS))


def _plugin(root: XmlElement, filename: str) -> XmlElement | None:
    return next((p for p in root.iter('plugin') if p.attrib.get('filename', '').endswith(filename)), None)


def _sensor(root: XmlElement, types: tuple[str, ...]) -> tuple[XmlElement, XmlElement] | None:
    """(the link holding it, the sensor) of the first sensor of one of `types`, or None."""
    for link in root.iter('link'):
        sensor = next((s for s in link.findall('sensor') if s.attrib.get('type') in types), None)
        if sensor is not None:
            return link, sensor
    for gazebo in root.iter('gazebo'):        # URDF: <gazebo reference="link"><sensor>
        sensor = next((s for s in gazebo.findall('sensor') if s.attrib.get('type') in types), None)
        if sensor is not None:
            return XmlElement('link', {'name': gazebo.attrib.get('reference', '')}, gazebo.line), sensor
    return None


def _number(parent: XmlElement, tag: str, default: float, source: str) -> float:
    element = next(parent.iter(tag), None)
    return numbers(element, 1, source)[0] if element is not None else default


def _rate(parent: XmlElement, default: float, source: str) -> float:
    """`update_rate` [Hz]; Gazebo's 0 (as fast as possible) is every physics step."""
    element = parent.find('update_rate')
    rate = numbers(element, 1, source)[0] if element is not None else default
    if rate < 0:
        raise SdfError(f'{source}:{element.line}: update_rate must be >= 0, got {rate:g}')
    return rate if rate > 0 else _EVERY_STEP


def _remapped(plugin: XmlElement, *names: str) -> str:
    """The target of a `<ros><remapping>NAME:=TARGET` for one of `names`, or ''."""
    for remapping in plugin.iter('remapping'):
        name, _, target = remapping.text.strip().partition(':=')
        if name.strip() in names and target.strip():
            return target.strip()
    return ''


def _drive(plugin: XmlElement, source: str) -> DiffDrivePlugin:
    element = plugin.find('odometry_source')
    try:
        odometry = odometry_source(element.text) if element is not None else 'world'
    except ValueError as exc:
        raise SdfError(f'{source}:{element.line}: {exc}') from None
    return DiffDrivePlugin(
        odometry_source=odometry,
        publish_odom=flag(plugin, 'publish_odom', False, source),
        publish_odom_tf=flag(plugin, 'publish_odom_tf', False, source),
        publish_wheel_tf=flag(plugin, 'publish_wheel_tf', False, source),
        odometry_frame=plugin.findtext('odometry_frame', 'odom') or 'odom',
        robot_base_frame=plugin.findtext('robot_base_frame', 'base_footprint') or 'base_footprint',
        update_rate=_rate(plugin, 100.0, source),
        cmd_vel_topic=_remapped(plugin, 'cmd_vel') or 'cmd_vel',
        odom_topic=_remapped(plugin, 'odom') or 'odom')


def _output(link: XmlElement, sensor: XmlElement, source: str) -> SensorOutput:
    """A sensor plugin's topic (`~/out` remapped, else `<plugin name>/out`) and frame."""
    plugin = sensor.find('plugin')
    name = plugin.attrib.get('name', sensor.attrib.get('name', 'sensor')) if plugin is not None else ''
    topic = (_remapped(plugin, '~/out') or f'{name}/out') if plugin is not None else f'{name or "sensor"}/out'
    frame = (plugin.findtext('frame_name') if plugin is not None else '') or link.attrib.get('name', '')
    return SensorOutput(topic, frame, _rate(sensor, 0.0, source))


def _imu(sensor: XmlElement, source: str) -> ImuSpec:
    gyro = next(sensor.iter('angular_velocity'), None)
    accel = next(sensor.iter('linear_acceleration'), None)
    return ImuSpec(rate=_rate(sensor, 0.0, source),
                   gyro_noise_stddev=_number(gyro, 'stddev', 0.0, source) if gyro is not None else 0.0,
                   accel_noise_stddev=_number(accel, 'stddev', 0.0, source) if accel is not None else 0.0)


def _lidar(sensor: XmlElement, source: str) -> LidarSpec:
    """A ray sensor's scan (its horizontal fan) as a LidarSpec; missing values are the LDS-01's."""
    lidar = LidarSpec(samples=int(_number(sensor, 'samples', LDS_01.samples, source)),
                      angle_min=_number(sensor, 'min_angle', LDS_01.angle_min, source),
                      angle_max=_number(sensor, 'max_angle', LDS_01.angle_max, source),
                      range_min=_number(sensor, 'min', LDS_01.range_min, source),
                      range_max=_number(sensor, 'max', LDS_01.range_max, source),
                      noise_stddev=_number(sensor, 'stddev', LDS_01.noise_stddev, source),
                      rate=_rate(sensor, 0.0, source))
    if lidar.samples < 2 or not lidar.angle_max > lidar.angle_min or not 0 <= lidar.range_min < lidar.range_max:
        raise SdfError(f'{source}:{sensor.line}: ray sensor needs samples >= 2, max_angle > min_angle and '
                       '0 <= range min < max')
    return lidar
