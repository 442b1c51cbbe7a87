"""zros.sim.gz_bridge: ros_gz_bridge's YAML and command-line forms, and their one-line errors."""
from __future__ import annotations

import pytest

from zros.sim.gz_bridge import BridgeConfigError, BridgeEntry, Direction, gz_side_type, parse_bridge_argument, \
    parse_bridge_config
from zros.sim.gz_topics import gz_key, gz_name

# In the shape of nav2_minimal_tb3_sim's configs/turtlebot3_waffle_bridge.yaml, plus the other
# ways ros_gz_bridge's README lets an entry name its topics.
CONFIG = '''
- topic_name: "/clock"
  ros_type_name: "rosgraph_msgs/msg/Clock"
  gz_type_name: "gz.msgs.Clock"
  direction: GZ_TO_ROS
- topic_name: "scan"
  ros_type_name: "sensor_msgs/msg/LaserScan"
  gz_type_name: "gz.msgs.LaserScan"
  direction: GZ_TO_ROS
  lazy: true
- ros_topic_name: "cmd_vel"
  gz_topic_name: "/model/bot/cmd_vel"
  ros_type_name: "geometry_msgs/msg/Twist"
  gz_type_name: "ignition.msgs.Twist"
  direction: ROS_TO_GZ
  subscriber_queue: 5
- gz_topic_name: "chatter"
  ros_type_name: "std_msgs/msg/String"
  gz_type_name: "gz.msgs.StringMsg"
'''


def test_each_way_of_naming_an_entry() -> None:
    clock, scan, cmd, chatter = parse_bridge_config(CONFIG, 'b.yaml')
    assert clock == BridgeEntry('/clock', '/clock', 'rosgraph_msgs/msg/Clock', 'gz.msgs.Clock', Direction.GZ_TO_ROS)
    assert scan.lazy and scan.ros_topic == scan.gz_topic == 'scan'
    assert (cmd.ros_topic, cmd.gz_topic, cmd.gz_type, cmd.subscriber_queue) == ('cmd_vel', '/model/bot/cmd_vel',
                                                                               'gz.msgs.Twist', 5)
    assert (chatter.ros_topic, chatter.direction) == ('chatter', Direction.BIDIRECTIONAL)
    assert parse_bridge_config('') == []


@pytest.mark.parametrize('argument, direction', [('/chatter@std_msgs/msg/String@gz.msgs.StringMsg', Direction.BIDIRECTIONAL),
                                                 ('/chatter@std_msgs/msg/String[gz.msgs.StringMsg', Direction.GZ_TO_ROS),
                                                 ('/chatter@std_msgs/msg/String]gz.msgs.StringMsg', Direction.ROS_TO_GZ)])
def test_the_command_line_form(argument: str, direction: Direction) -> None:
    entry = parse_bridge_argument(argument)
    assert (entry.ros_topic, entry.gz_topic, entry.ros_type, entry.direction) == ('/chatter', '/chatter',
                                                                                   'std_msgs/msg/String', direction)


def test_the_gazebo_side_carries_the_first_ros_type_of_its_gz_type() -> None:
    stamped = parse_bridge_argument('cmd_vel@geometry_msgs/msg/TwistStamped]gz.msgs.Twist')
    assert gz_side_type(stamped) == 'geometry_msgs/msg/Twist'
    assert gz_side_type(parse_bridge_argument('tf@tf2_msgs/msg/TFMessage[gz.msgs.Pose_V')) == 'tf2_msgs/msg/TFMessage'


@pytest.mark.parametrize('text, message', [
    ('- {ros_type_name: a}', "b.yaml: entry 1: gz_type_name is required"),
    ('- {topic_name: s, ros_type_name: sensor_msgs/msg/LaserScan, gz_type_name: gz.msgs.LaserScan, direction: UP}',
     "b.yaml: entry 1: direction must be BIDIRECTIONAL, GZ_TO_ROS or ROS_TO_GZ, got 'UP'"),
    ('- {topic_name: s, ros_type_name: sensor_msgs/msg/Imu, gz_type_name: gz.msgs.LaserScan}',
     'b.yaml: entry 1: no bridge between ROS type sensor_msgs/msg/Imu and Gazebo type gz.msgs.LaserScan '
     '(it pairs with sensor_msgs/msg/LaserScan)'),
    ('- {topic: s, ros_type_name: x, gz_type_name: y}', "b.yaml: entry 1: unknown key 'topic'"),
    ('- {ros_type_name: std_msgs/msg/String, gz_type_name: gz.msgs.StringMsg}',
     'b.yaml: entry 1: one of topic_name, ros_topic_name, gz_topic_name is required'),
    ('topic_name: s', 'b.yaml: expected a YAML list of maps, got dict'),
    ('- [a', 'b.yaml:1: invalid YAML'),
])
def test_bad_configurations_are_one_line(text: str, message: str) -> None:
    with pytest.raises(BridgeConfigError) as error:
        parse_bridge_config(text, 'b.yaml')
    assert str(error.value).startswith(message) and '\n' not in str(error.value)


def test_bad_arguments_are_one_line() -> None:
    with pytest.raises(BridgeConfigError, match=r"^bridge argument 'scan': expected topic@ros_type@gz_type"):
        parse_bridge_argument('scan')
    with pytest.raises(BridgeConfigError, match=r'no bridge between ROS type std_msgs/msg/String and Gazebo type gz.msgs.Nope$'):
        parse_bridge_argument('s@std_msgs/msg/String[gz.msgs.Nope')


def test_gazebo_names_live_under_the_hidden_prefix() -> None:
    assert gz_name('scan') == '/scan' and gz_name('scan', 'tb3') == '/tb3/scan' and gz_name('/abs', 'tb3') == '/abs'
    assert gz_key('/clock') == '/_gz/clock' and gz_key('scan', '/tb3/') == '/_gz/tb3/scan'
