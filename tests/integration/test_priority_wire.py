"""Zenoh priority and express as a stranger's subscriber sees them (the choice itself:
tests/unit/test_priority.py): velocity commands first, maps last, keys unchanged."""
from __future__ import annotations

import os
import threading
import time

import zenoh

from conftest import assert_clean_failure, run_cli
from zros.keys import topic_key
from zros.node import Node
from zros.qos import DurabilityPolicy, QoSProfile

from interfaces.geometry_msgs.msg import Twist
from interfaces.nav_msgs.msg import OccupancyGrid
from interfaces.std_msgs.msg import String


def test_samples_carry_the_topics_priority_to_a_plain_zenoh_subscriber(context, raw_session, monkeypatch):
    monkeypatch.setenv('ZROS_TOPIC_PRIORITY', '/chatter=background')
    wanted = {'robot1/cmd_vel': (zenoh.Priority.REAL_TIME, True),
              'map': (zenoh.Priority.DATA_LOW, False),
              'chatter': (zenoh.Priority.BACKGROUND, False),     # the rule
              'other': (zenoh.Priority.DATA, False)}             # Zenoh's default
    seen: dict[str, tuple[zenoh.Priority, bool]] = {}
    all_in = threading.Event()

    def on_sample(sample: zenoh.Sample) -> None:
        seen[str(sample.key_expr).rsplit('/t/', 1)[1]] = (sample.priority, sample.express)
        if len(seen.keys() & wanted) == len(wanted):
            all_in.set()
    subscriber = raw_session.declare_subscriber(topic_key(context.domain_id, '/**'), on_sample)
    node = Node('prio_pub', namespace='/robot1', context=context)
    sends = [(node.create_publisher(Twist, 'cmd_vel', 10), Twist()),          # relative: /robot1/cmd_vel
             (node.create_publisher(OccupancyGrid, '/map', QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL)),
              OccupancyGrid()),
             (node.create_publisher(String, '/chatter', 10), String(data='hi')),
             (node.create_publisher(String, '/other', 10), String(data='hi'))]
    deadline = time.monotonic() + 10
    while not all_in.is_set() and time.monotonic() < deadline:
        for publisher, msg in sends:
            publisher.publish(msg)
        all_in.wait(0.1)
    subscriber.undeclare()
    assert {key: seen.get(key) for key in wanted} == wanted


def test_a_bad_setting_stops_a_node_with_one_line(domain):
    result = run_cli('run', 'demo_nodes', 'talker', timeout=30,
                     env={**os.environ, 'ZROS_TOPIC_PRIORITY': '/cmd_vel=fastest'})
    assert_clean_failure(result, 'ZROS_TOPIC_PRIORITY', "unknown priority 'fastest'")
