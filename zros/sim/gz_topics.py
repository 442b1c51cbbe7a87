"""Gazebo Sim's topic names, and where they live in zros: a hidden key space under `/_gz`.

    gz_key('/scan')                          # '/_gz/scan': the simulator publishes here
    gz_key('scan', namespace='tb3')          # '/_gz/tb3/scan' (the bridge's expand_gz_topic_names)
    default_topics('turtlebot3_waffle', 'default').odom    # '/model/turtlebot3_waffle/odometry'

In Gazebo Sim (Harmonic), a robot's sensors and systems publish on Gazebo Transport, not on ROS:
nothing reaches `/scan` until a `ros_gz_bridge` relays it. zros keeps that shape with one
session: the Gazebo side is the hidden prefix `/_gz` (a name token that starts with `_` is hidden
from `zros topic list`, as ROS hides them), so `/_gz/scan` is Gazebo's `/scan` and no ROS node
sees it unless the bridge republishes it. Messages on the Gazebo side are already the ROS types
the bridge pairs with each Gazebo type (zros.sim.gz_bridge), so the relay copies bytes.

The defaults are Gazebo Sim's for a model that does not name its topics or frames.
"""
from __future__ import annotations

from typing import NamedTuple

__all__ = ['GZ_PREFIX', 'gz_key', 'gz_name', 'RobotTopics', 'default_topics', 'ros_topics']

#: The hidden prefix of the Gazebo side's topics and services.
GZ_PREFIX = '/_gz'


def gz_name(topic: str, namespace: str = '') -> str:
    """A Gazebo topic name made absolute: `scan` -> `/scan`, or `/ns/scan` under `namespace`
    (absolute names stay as they are, as with ROS's expansion)."""
    topic = topic.strip()
    if topic.startswith('/'):
        return '/' + topic.strip('/')
    parts = [part for part in (namespace.strip('/'), topic.strip('/')) if part]
    return '/' + '/'.join(parts)


def gz_key(topic: str, namespace: str = '') -> str:
    """The zros topic that carries Gazebo topic `topic`: `/_gz` + its absolute name."""
    return GZ_PREFIX + gz_name(topic, namespace)


class RobotTopics(NamedTuple):
    """Where a simulated robot's data goes, and its frames; the topics are full names.

    The simulator node subscribes `cmd_vel` and publishes the rest, stamping its messages with
    these frames. `namespace` is the robot's ROS namespace (for zros's own `sim/` ground truth).
    """
    cmd_vel: str
    odom: str
    tf: str
    joint_states: str
    scan: str
    imu: str
    namespace: str = ''
    odom_frame: str = 'odom'
    base_frame: str = 'base_footprint'
    scan_frame: str = 'base_scan'
    imu_frame: str = 'imu_link'


def ros_topics(namespace: str) -> RobotTopics:
    """The TurtleBot3's own ROS topics (Gazebo classic's plugins, the real robot) under `namespace`."""
    namespace = namespace.strip('/')
    prefix = f'/{namespace}/' if namespace else ''
    return RobotTopics(*(prefix + name for name in ('cmd_vel', 'odom', 'tf', 'joint_states', 'scan', 'imu')),
                       namespace=namespace)


def default_topics(model: str, world: str, *, lidar: tuple[str, str] = ('base_scan', 'lidar'),
                   imu: tuple[str, str] = ('imu_link', 'imu')) -> RobotTopics:
    """Gazebo Sim's names for a model's topics when its plugins and sensors name none (as Gazebo
    topic names, not yet under GZ_PREFIX); `lidar` and `imu` are the sensors' (link, sensor)."""
    sensor = f'/world/{world}/model/{model}/link/{{}}/sensor/{{}}/{{}}'
    return RobotTopics(cmd_vel=f'/model/{model}/cmd_vel', odom=f'/model/{model}/odometry',
                       tf=f'/model/{model}/tf', joint_states=f'/world/{world}/model/{model}/joint_state',
                       scan=sensor.format(*lidar, 'scan'), imu=sensor.format(*imu, 'imu'),
                       namespace=f'model/{model}', odom_frame=f'{model}/odom', base_frame=f'{model}/base_footprint',
                       scan_frame=f'{model}::{lidar[0]}::{lidar[1]}', imu_frame=f'{model}::{imu[0]}::{imu[1]}')
