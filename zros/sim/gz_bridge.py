"""ros_gz_bridge's configuration: which topics cross between Gazebo and ROS, of which types, which way.

    entries = parse_bridge_config(Path('configs/turtlebot3_waffle_bridge.yaml').read_text(), 'bridge.yaml')
    entry = parse_bridge_argument('/scan@sensor_msgs/msg/LaserScan[gz.msgs.LaserScan')
    entry.ros_topic, entry.gz_topic, entry.direction      # '/scan', '/scan', Direction.GZ_TO_ROS

The two forms ros_gz_bridge's `parameter_bridge` takes: a YAML list of maps (`config_file:=`:
`topic_name`, or `ros_topic_name` and/or `gz_topic_name`; `ros_type_name`, `gz_type_name`,
`direction` BIDIRECTIONAL / GZ_TO_ROS / ROS_TO_GZ, `lazy`, `subscriber_queue`, `publisher_queue`),
and its command-line arguments `topic@ros_type@gz_type` (both ways), `topic@ros_type[gz_type`
(Gazebo to ROS), `topic@ros_type]gz_type` (ROS to Gazebo).

zros's simulator already carries ROS messages on the Gazebo side (zros.sim.gz_topics), so a
bridge is a relay: the pair of types must be one ros_gz_bridge supports (`GZ_TYPES`), and the
Gazebo side carries the first ROS type listed for its Gazebo type. Errors are one line naming
the file and entry.
"""
from __future__ import annotations

import enum
from typing import Any, NamedTuple

import yaml

__all__ = ['Direction', 'BridgeEntry', 'BridgeConfigError', 'GZ_TYPES', 'parse_bridge_config',
           'parse_bridge_argument', 'gz_side_type']


class BridgeConfigError(ValueError):
    """A bridge configuration that cannot be used; the message is one line."""


class Direction(enum.Enum):
    BIDIRECTIONAL = 'BIDIRECTIONAL'
    GZ_TO_ROS = 'GZ_TO_ROS'
    ROS_TO_GZ = 'ROS_TO_GZ'


#: Gazebo Transport type -> the ROS types ros_gz_bridge pairs with it (its README's table, the
#: types a robot simulation uses); the first is what zros's Gazebo side carries.
GZ_TYPES: dict[str, tuple[str, ...]] = {
    'gz.msgs.Clock': ('rosgraph_msgs/msg/Clock',),
    'gz.msgs.LaserScan': ('sensor_msgs/msg/LaserScan',),
    'gz.msgs.IMU': ('sensor_msgs/msg/Imu',),
    'gz.msgs.Model': ('sensor_msgs/msg/JointState',),
    'gz.msgs.Odometry': ('nav_msgs/msg/Odometry',),
    'gz.msgs.OdometryWithCovariance': ('nav_msgs/msg/Odometry',),
    'gz.msgs.Pose_V': ('tf2_msgs/msg/TFMessage', 'geometry_msgs/msg/PoseArray'),
    'gz.msgs.Pose': ('geometry_msgs/msg/Pose', 'geometry_msgs/msg/PoseStamped', 'geometry_msgs/msg/Transform',
                     'geometry_msgs/msg/TransformStamped'),
    'gz.msgs.Twist': ('geometry_msgs/msg/Twist', 'geometry_msgs/msg/TwistStamped'),
    'gz.msgs.Image': ('sensor_msgs/msg/Image',),
    'gz.msgs.CameraInfo': ('sensor_msgs/msg/CameraInfo',),
    'gz.msgs.PointCloudPacked': ('sensor_msgs/msg/PointCloud2',),
    'gz.msgs.NavSat': ('sensor_msgs/msg/NavSatFix',),
    'gz.msgs.BatteryState': ('sensor_msgs/msg/BatteryState',),
    'gz.msgs.Joy': ('sensor_msgs/msg/Joy',),
    'gz.msgs.Boolean': ('std_msgs/msg/Bool',),
    'gz.msgs.Empty': ('std_msgs/msg/Empty',),
    'gz.msgs.Float': ('std_msgs/msg/Float32',),
    'gz.msgs.Double': ('std_msgs/msg/Float64',),
    'gz.msgs.Int32': ('std_msgs/msg/Int32',),
    'gz.msgs.UInt32': ('std_msgs/msg/UInt32',),
    'gz.msgs.StringMsg': ('std_msgs/msg/String',),
    'gz.msgs.Header': ('std_msgs/msg/Header',),
    'gz.msgs.Time': ('builtin_interfaces/msg/Time',),
    'gz.msgs.Vector3d': ('geometry_msgs/msg/Vector3', 'geometry_msgs/msg/Point'),
    'gz.msgs.Wrench': ('geometry_msgs/msg/Wrench', 'geometry_msgs/msg/WrenchStamped'),
}
_KEYS = {'topic_name', 'ros_topic_name', 'gz_topic_name', 'ros_type_name', 'gz_type_name', 'direction', 'lazy',
         'subscriber_queue', 'publisher_queue'}
_DELIMITERS = {'@': Direction.BIDIRECTIONAL, '[': Direction.GZ_TO_ROS, ']': Direction.ROS_TO_GZ}


class BridgeEntry(NamedTuple):
    """One bridged topic. Topic names are as written (relative ones resolve in the bridge node's
    namespace); `gz_type` is normalised to `gz.msgs.*`."""
    ros_topic: str
    gz_topic: str
    ros_type: str
    gz_type: str
    direction: Direction = Direction.BIDIRECTIONAL
    lazy: bool = False
    subscriber_queue: int = 10
    publisher_queue: int = 10


def gz_side_type(entry: BridgeEntry) -> str:
    """The ROS type zros's Gazebo side carries for the entry's Gazebo type."""
    return GZ_TYPES[entry.gz_type][0]


def _checked(entry: BridgeEntry, where: str) -> BridgeEntry:
    gz_type = entry.gz_type.replace('ignition.msgs.', 'gz.msgs.').replace('gz::msgs::', 'gz.msgs.')
    ros_type = entry.ros_type if '/msg/' in entry.ros_type else entry.ros_type.replace('/', '/msg/', 1)
    entry = entry._replace(gz_type=gz_type, ros_type=ros_type)
    if gz_type not in GZ_TYPES or ros_type not in GZ_TYPES[gz_type]:
        raise BridgeConfigError(f'{where}: no bridge between ROS type {entry.ros_type} and Gazebo type '
                                f'{entry.gz_type}' + (f' (it pairs with {", ".join(GZ_TYPES[gz_type])})'
                                                      if gz_type in GZ_TYPES else ''))
    return entry


def parse_bridge_argument(argument: str) -> BridgeEntry:
    """One command-line bridge, `topic@ros_type(@|[|])gz_type`; BridgeConfigError if malformed."""
    topic, at, rest = argument.partition('@')
    index = min((i for i in (rest.find(d) for d in _DELIMITERS) if i >= 0), default=-1)
    if not topic or not at or index <= 0 or index == len(rest) - 1:
        raise BridgeConfigError(f"bridge argument '{argument}': expected topic@ros_type@gz_type (both ways), "
                                'topic@ros_type[gz_type (Gazebo to ROS) or topic@ros_type]gz_type (ROS to Gazebo)')
    entry = BridgeEntry(topic, topic, rest[:index], rest[index + 1:], _DELIMITERS[rest[index]])
    return _checked(entry, f"bridge argument '{argument}'")


def parse_bridge_config(text: str, source: str = '<config>') -> list[BridgeEntry]:
    """The entries of a YAML bridge configuration; BridgeConfigError (`source: entry N: what`)."""
    try:
        data = yaml.safe_load(text)
    except yaml.YAMLError as exc:
        mark = getattr(exc, 'problem_mark', None)
        raise BridgeConfigError(f'{source}:{mark.line + 1 if mark else "?"}: invalid YAML: '
                                f'{getattr(exc, "problem", exc)}') from None
    if data is None:
        return []
    if not isinstance(data, list):
        raise BridgeConfigError(f'{source}: expected a YAML list of maps, got {type(data).__name__}')
    return [_entry(item, f'{source}: entry {number}') for number, item in enumerate(data, 1)]


def _entry(item: Any, where: str) -> BridgeEntry:
    if not isinstance(item, dict):
        raise BridgeConfigError(f'{where}: expected a map, got {item!r}')
    unknown = sorted(set(map(str, item)) - _KEYS)
    if unknown:
        raise BridgeConfigError(f"{where}: unknown key '{unknown[0]}' (known: {', '.join(sorted(_KEYS))})")
    for key in ('ros_type_name', 'gz_type_name'):
        if not isinstance(item.get(key), str) or not item[key]:
            raise BridgeConfigError(f'{where}: {key} is required')
    topic = item.get('topic_name')
    if topic is not None and ('ros_topic_name' in item or 'gz_topic_name' in item):
        raise BridgeConfigError(f'{where}: topic_name cannot go with ros_topic_name or gz_topic_name')
    ros_topic = str(item.get('ros_topic_name') or topic or item.get('gz_topic_name') or '')
    gz_topic = str(item.get('gz_topic_name') or topic or ros_topic)
    if not ros_topic:
        raise BridgeConfigError(f'{where}: one of topic_name, ros_topic_name, gz_topic_name is required')
    direction = str(item.get('direction', 'BIDIRECTIONAL'))
    if direction not in Direction.__members__:
        raise BridgeConfigError(f"{where}: direction must be BIDIRECTIONAL, GZ_TO_ROS or ROS_TO_GZ, got '{direction}'")
    queues = {}
    for key in ('subscriber_queue', 'publisher_queue'):
        value = item.get(key, 10)
        if isinstance(value, bool) or not isinstance(value, int) or value < 1:
            raise BridgeConfigError(f'{where}: {key} must be a positive integer, got {value!r}')
        queues[key] = value
    lazy = item.get('lazy', False)
    if isinstance(lazy, str) and lazy.lower() in ('true', 'false'):
        lazy = lazy.lower() == 'true'
    if not isinstance(lazy, bool):
        raise BridgeConfigError(f'{where}: lazy must be true or false, got {lazy!r}')
    entry = BridgeEntry(ros_topic, gz_topic, item['ros_type_name'], item['gz_type_name'], Direction[direction],
                        lazy, queues['subscriber_queue'], queues['publisher_queue'])
    return _checked(entry, where)
