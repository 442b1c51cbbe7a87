"""zros.priority: which topics jump Zenoh's queues, and the ZROS_TOPIC_PRIORITY rules."""
from __future__ import annotations

import pytest

from zros.errors import ZrosError
from zros.priority import PRIORITIES, TransportPriority, parse_topic_priorities, transport_priority

URGENT = TransportPriority('real_time', True)


@pytest.mark.parametrize('topic', ['/cmd_vel', '/robot1/cmd_vel', '/cmd_vel_nav', '/cmd_vel_teleop'])
def test_velocity_commands_go_first_and_unbatched(topic: str) -> None:
    assert transport_priority(topic, 'geometry_msgs/msg/Twist', ()) == URGENT
    assert transport_priority(topic, 'geometry_msgs/msg/TwistStamped', ()) == URGENT


def test_tf_comes_next_and_big_messages_go_last() -> None:
    assert transport_priority('/tf', 'tf2_msgs/msg/TFMessage', ()) == ('interactive_high', True)
    assert transport_priority('/tf_static', 'tf2_msgs/msg/TFMessage', ()) == ('interactive_high', True)
    for topic, type_name in [('/map', 'nav_msgs/msg/OccupancyGrid'),
                             ('/global_costmap/costmap', 'nav_msgs/msg/OccupancyGrid'),
                             ('/global_costmap/costmap_raw', 'nav2_msgs/msg/Costmap'),
                             ('/global_costmap/costmap_updates', 'map_msgs/msg/OccupancyGridUpdate'),
                             ('/camera/image_raw', 'sensor_msgs/msg/Image')]:
        assert transport_priority(topic, type_name, ()) == ('data_low', False), topic


def test_everything_else_keeps_zenohs_default() -> None:
    for topic, type_name in [('/scan', 'sensor_msgs/msg/LaserScan'), ('/odom', 'nav_msgs/msg/Odometry'),
                             ('/cmd_velocity', 'geometry_msgs/msg/Twist'), ('/chatter', 'std_msgs/msg/String')]:
        assert transport_priority(topic, type_name, ()) == ('data', False), topic


def test_rules_replace_the_defaults_first_match_first() -> None:
    rules = parse_topic_priorities('/cmd_vel=interactive_low, /camera/*=7,/*/image=2:express,/scan=data_high:express')
    assert transport_priority('/cmd_vel', 'geometry_msgs/msg/Twist', rules) == ('interactive_low', False)
    assert transport_priority('/camera/left/image', 'sensor_msgs/msg/Image', rules) == ('background', False)
    assert transport_priority('/front/image', 'sensor_msgs/msg/Image', rules) == ('interactive_high', True)
    assert transport_priority('/scan', 'sensor_msgs/msg/LaserScan', rules) == ('data_high', True)
    assert transport_priority('/tf', 'tf2_msgs/msg/TFMessage', rules) == ('interactive_high', True)   # unmatched


def test_numbers_are_zenohs_one_to_seven() -> None:
    rules = parse_topic_priorities(','.join(f'/t{n}={n}' for n in range(1, 8)))
    assert [setting.priority for _, setting in rules] == list(PRIORITIES)
    assert parse_topic_priorities('') == () and parse_topic_priorities(' , ') == ()


def test_the_environment_is_read(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv('ZROS_TOPIC_PRIORITY', '/chatter=REAL-TIME:express')
    assert transport_priority('/chatter', 'std_msgs/msg/String') == URGENT
    monkeypatch.delenv('ZROS_TOPIC_PRIORITY')
    assert transport_priority('/chatter', 'std_msgs/msg/String') == ('data', False)


@pytest.mark.parametrize('text, message', [
    ('/cmd_vel', 'is not TOPIC=PRIORITY'),
    ('cmd_vel=real_time', 'is not TOPIC=PRIORITY'),
    ('/cmd_vel=urgent', "unknown priority 'urgent'"),
    ('/cmd_vel=8', "unknown priority '8'"),
    ('/cmd_vel=real_time:fast', "unknown flag 'fast'"),
])
def test_a_bad_rule_is_one_line_naming_the_setting(text: str, message: str) -> None:
    with pytest.raises(ZrosError, match=message) as caught:
        parse_topic_priorities(text)
    assert str(caught.value).startswith('ZROS_TOPIC_PRIORITY: ') and '\n' not in str(caught.value)
