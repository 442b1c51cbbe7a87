"""`zros run topic_tools throttle|drop|relay` as processes: typed by the graph, rates as asked."""
from __future__ import annotations

import sys
import time

from zros.executors import SingleThreadedExecutor
from zros.node import Node

from interfaces.std_msgs.msg import String


def _count(context, topics: list[str]) -> tuple[SingleThreadedExecutor, dict[str, list[float]]]:
    node = Node('topic_tools_probe', context=context)
    seen: dict[str, list[float]] = {t: [] for t in topics}
    for topic in topics:
        node.create_subscription(String, topic, lambda m, t=topic: seen[t].append(time.monotonic()), 100)
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(node)
    return executor, seen


def test_throttle_drop_and_relay_of_a_20_hz_topic(domain, spawn, context, spin_for, zros_cli):
    spawn(sys.executable, '-m', 'zros.cli.main', 'topic', 'pub', '-r', '20', '/chatter', 'std_msgs/msg/String',
          '{data: hi}', name='pub')
    spawn.run('topic_tools', 'throttle', 'messages', '/chatter', '4')
    spawn.run('topic_tools', 'drop', '/chatter', '1', '2', '/half')
    spawn.run('topic_tools', 'relay', '/chatter', '--ros-args', '-p', 'lazy:=true')
    executor, seen = _count(context, ['/chatter', '/chatter_throttle', '/half', '/chatter_relay'])
    spin_for(executor, lambda: all(len(v) >= 3 for v in seen.values()), timeout=20,
             message=lambda: f'messages on every output: { {k: len(v) for k, v in seen.items()} }')
    for v in seen.values():
        v.clear()
    spin_for(executor, lambda: False if len(seen['/chatter']) < 60 else True, timeout=10,
             message='3 s of the input')
    n = {k: len(v) for k, v in seen.items()}
    assert 10 <= n['/chatter_throttle'] <= 14, n            # 4 Hz of 20 Hz over 3 s
    assert abs(n['/half'] - n['/chatter'] / 2) <= 3, n
    assert abs(n['/chatter_relay'] - n['/chatter']) <= 3, n
    listed = zros_cli('topic', 'list', '-t').stdout
    for topic in ('/chatter_throttle', '/half', '/chatter_relay'):
        assert f'{topic} [std_msgs/msg/String]' in listed, listed     # the type came from the graph


def test_a_lazy_relay_subscribes_only_while_someone_listens(domain, spawn, zros_cli, wait_for):
    spawn(sys.executable, '-m', 'zros.cli.main', 'topic', 'pub', '-r', '5', '/scan_like', 'std_msgs/msg/String',
          '{data: x}', name='pub')
    spawn.run('topic_tools', 'relay', '/scan_like', '/far', '--ros-args', '-p', 'lazy:=true')

    def subscribers() -> str:
        return zros_cli('topic', 'info', '/scan_like').stdout
    wait_for(lambda: 'Publisher count: 1' in subscribers() and 'Subscription count: 0' in subscribers(), timeout=15,
             message=lambda: f'no subscription on the input while nobody listens: {subscribers()}')
    echo = zros_cli('topic', 'echo', '--once', '--timeout', '10', '/far', timeout=20)
    assert 'data: x' in echo.stdout, echo
