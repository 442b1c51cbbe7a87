"""Robots from their model files: what a model's Gazebo plugins and sensors say it does.

    robot = robot_from_xml(open('models/turtlebot3_burger/model.sdf').read(), fallback='burger')
    robot.spec.wheel_separation, robot.lidar.samples, robot.drive.odometry_source, robot.warning

A model file (an SDF `<model>`, or a URDF `<robot>` with `<gazebo>` tags) tells Gazebo how the
robot drives, senses and what it publishes; zros reads the same elements, with the defaults of
Gazebo's plugins where an element is absent. Gazebo classic (gazebo_plugins, ROS 2):
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
Gazebo Sim (Harmonic):
- the diff-drive system (`gz-sim-diff-drive-system`): `wheel_separation`, `wheel_radius`,
  `max_linear_acceleration`, `max_linear_velocity`, `max_angular_velocity`,
  `odom_publish_frequency` (50), and where it talks: `topic`, `odom_topic`, `tf_topic`,
  `frame_id`, `child_frame_id`; it always publishes odometry and its TF, integrated from the
  wheels from zero at the model's start (zros's `encoder` odometry source);
- the first lidar (`"gpu_lidar"`, `"lidar"`, or a ray sensor) and IMU: their numbers as above,
  their `topic` and `gz_frame_id`;
- `gz-sim-joint-state-publisher-system`: its `topic`, `update_rate` and `joint_name`s.
Where a Gazebo Sim model says nothing, its topics and frames are Gazebo's defaults
(zros.sim.gz_topics); `RobotModel.topics` holds them, as Gazebo topic names, and its outputs
(`drive`, `scan`, `imu_output`, `joint_states`) carry the same names and frames.
A sensor or publisher the file lacks is not published (Gazebo publishes only what its plugins
say). The rest of the robot (body disc, mounts, speed limits) is the robot whose wheels the Gazebo
Sim diff-drive plugin states (the TurtleBot4's Create 3 base: separation 0.233 m, radius
0.03575 m), else the TurtleBot3 the XML names (`waffle_pi`, `waffle`, `burger`), else `fallback`
($TURTLEBOT3_MODEL). A model without a
diff-drive plugin is that TurtleBot3 as ROBOTIS's model file describes it, with a one-line
`warning`.
"""
from __future__ import annotations

from dataclasses import dataclass, replace
from typing import NamedTuple

from zros.sim.gz_topics import RobotTopics, default_topics, gz_name
from zros.sim.robot import TURTLEBOT4, RobotSpec, odometry_source, robot_spec
from zros.sim.sdf import SdfError, XmlElement, flag, numbers, parse_xml
from zros.sim.sensors import LDS_01, TURTLEBOT3_IMU, ImuSpec, LidarSpec

__all__ = ['RobotModel', 'DiffDrivePlugin', 'SensorOutput', 'JointStateOutput', 'robot_from_xml',
           'turtlebot3_named', 'turtlebot3_model', 'TURTLEBOT3_DRIVE', 'TURTLEBOT3_SCAN', 'TURTLEBOT3_IMU_OUTPUT',
           'TURTLEBOT3_JOINT_STATES', 'WHEEL_JOINTS']

_DIFF_DRIVE = 'libgazebo_ros_diff_drive.so'
_JOINT_STATES = 'libgazebo_ros_joint_state_publisher.so'
_LIDARS = ('ray', 'gpu_ray', 'gpu_lidar', 'lidar')
#: Gazebo Sim's systems, by a part of the plugin's `filename` (`gz-sim-...`, `libgz-sim8-...so`,
#: Fortress's `ignition-gazebo-...`) or its class `name`.
_GZ_DIFF_DRIVE = ('diff-drive-system', 'systems::DiffDrive')
_GZ_JOINT_STATES = ('joint-state-publisher-system', 'systems::JointStatePublisher')
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
#: Robots known by their wheels (a model file names no robot zros could look up otherwise).
_BY_WHEELS = (TURTLEBOT4,)
_WHEEL_TOLERANCE = 1e-4    # [m]


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
    topics: RobotTopics | None = None   # Gazebo Sim's topic names and frames (None for a classic model)


def turtlebot3_named(xml: str, fallback: str) -> str:
    """The TurtleBot3 model an XML text names (waffle_pi before waffle), else `fallback`."""
    return next((m for m in ('waffle_pi', 'waffle', 'burger') if m in xml), fallback)


def turtlebot3_model(model: str) -> RobotModel:
    """A TurtleBot3 as ROBOTIS's model.sdf describes it (no file needed); ValueError if unknown."""
    return RobotModel(robot_spec(model), LDS_01, '')


def robot_from_xml(xml: str, *, fallback: str, source: str = '<robot XML>', world: str = 'default') -> RobotModel:
    """The robot an SDF or URDF text describes; SdfError (one line) if the XML is malformed.
    `world` is the world it goes into (Gazebo Sim's default topic names contain it)."""
    base = robot_spec(turtlebot3_named(xml, fallback))
    root = parse_xml(xml, source)
    model = root.find('model') if root.tag == 'sdf' else root
    name = model.attrib.get('name', '?') if model is not None else root.attrib.get('name', '?')
    classic = _plugin(root, (_DIFF_DRIVE,))
    gz = _plugin(root, _GZ_DIFF_DRIVE) if classic is None else None
    if classic is None and gz is None:
        return turtlebot3_model(base.model)._replace(
            warning=f"model '{name}' has no diff-drive plugin ({_DIFF_DRIVE} or gz-sim-diff-drive-system): "
                    f'simulating a TurtleBot3 {base.model}')
    ray = _sensor(root, _LIDARS)
    imu = _sensor(root, ('imu',))
    lidar = _lidar(ray[1], source) if ray else LDS_01
    imu_spec = _imu(imu[1], source) if imu else None
    if gz is not None:
        return _gz_model(root, model, name, world, gz, _robot_by_wheels(gz, base, source), lidar, ray, imu, imu_spec, source)
    spec = replace(base,
                   wheel_separation=_number(classic, 'wheel_separation', base.wheel_separation, source),
                   wheel_radius=_number(classic, 'wheel_diameter', 2 * base.wheel_radius, source) / 2,
                   max_wheel_acceleration=_number(classic, 'max_wheel_acceleration', base.max_wheel_acceleration,
                                                  source))
    _check(spec, classic, 'wheel_separation, wheel_diameter and max_wheel_acceleration', source)
    joint_states = _plugin(root, (_JOINT_STATES,))
    return RobotModel(
        spec, lidar, '', _drive(classic, source),
        scan=_output(*ray, source) if ray else None,
        imu=imu_spec,
        imu_output=_output(*imu, source) if imu else None,
        joint_states=None if joint_states is None else JointStateOutput(
            _remapped(joint_states, 'joint_states', '~/out') or 'joint_states',
            _rate(joint_states, 100.0, source), _joint_names(joint_states)))


def _gz_model(root: XmlElement, model: XmlElement | None, name: str, world: str, drive: XmlElement,
              base: RobotSpec, lidar: LidarSpec, ray: tuple[XmlElement, XmlElement] | None,
              imu: tuple[XmlElement, XmlElement] | None, imu_spec: ImuSpec | None, source: str) -> RobotModel:
    """A Gazebo Sim model: its diff-drive system's numbers, its topics and frames (RobotTopics),
    and its outputs with the same names and frames at the rates its systems and sensors say.
    Gazebo Sim's DiffDrive always publishes odometry and its TF, integrated from the wheel
    joints from zero at the start (math::DiffDriveOdometry): zros's `encoder` source."""
    spec = replace(base,
                   wheel_separation=_number(drive, 'wheel_separation', base.wheel_separation, source),
                   wheel_radius=_number(drive, 'wheel_radius', base.wheel_radius, source),
                   max_wheel_acceleration=_number(drive, 'max_linear_acceleration', base.max_wheel_acceleration,
                                                  source),
                   max_linear=_number(drive, 'max_linear_velocity', base.max_linear, source),
                   max_angular=_number(drive, 'max_angular_velocity', base.max_angular, source))
    _check(spec, drive, 'wheel_separation, wheel_radius, max_linear_acceleration and the maximum velocities', source)
    joints = _plugin(root, _GZ_JOINT_STATES)
    topics = _gz_topics(root, model, name, world, drive, joints, ray[1] if ray else None, imu[1] if imu else None)
    frequency = drive.find('odom_publish_frequency')
    odom_rate = numbers(frequency, 1, source)[0] if frequency is not None else 50.0
    if not odom_rate > 0:
        raise SdfError(f'{source}:{frequency.line}: odom_publish_frequency must be > 0, got {odom_rate:g}')
    return RobotModel(
        spec, lidar, '',
        DiffDrivePlugin(odometry_source='encoder', publish_odom=True, publish_odom_tf=True,
                        odometry_frame=topics.odom_frame, robot_base_frame=topics.base_frame, update_rate=odom_rate,
                        cmd_vel_topic=topics.cmd_vel, odom_topic=topics.odom),
        scan=SensorOutput(topics.scan, topics.scan_frame, lidar.rate) if ray else None,
        imu=imu_spec,
        imu_output=SensorOutput(topics.imu, topics.imu_frame, imu_spec.rate) if imu_spec else None,
        joint_states=None if joints is None else JointStateOutput(topics.joint_states, _rate(joints, 0.0, source),
                                                                  _joint_names(joints)),
        topics=topics)


def _joint_names(plugin: XmlElement) -> tuple[str, ...]:
    return tuple(e.text.strip() for e in plugin.iter('joint_name')) or WHEEL_JOINTS


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


def _gz_topics(root: XmlElement, model: XmlElement | None, name: str, world: str, drive: XmlElement,
               joints: XmlElement | None, lidar: XmlElement | None, imu: XmlElement | None) -> RobotTopics:
    """Gazebo Sim's topics and frames of a model: what its plugins and sensors say, else Gazebo's
    defaults (a sensor's default topic is scoped by its link and name)."""
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
