"""QoS events firing for real causes (deadlines passing, a publisher process dying, sequence
gaps, incompatible and matching endpoints appearing) and QoS overrides from parameters."""
from __future__ import annotations

import signal
import textwrap
import threading

import pytest

from zros.duration import Duration
from zros.event_handler import PublisherEventCallbacks, SubscriptionEventCallbacks
from zros.executors import SingleThreadedExecutor
from zros.node import Node
from zros.qos import LivelinessPolicy, QoSPolicyKind, QoSProfile, ReliabilityPolicy
from zros.qos_overriding_options import InvalidQosOverridesError, QosCallbackResult, QoSOverridingOptions

PUBLISHER = textwrap.dedent('''
    import sys, time
    import zros
    from zros.node import Node
    from zros.duration import Duration
    from zros.qos import QoSProfile
    from interfaces.std_msgs.msg import String

    zros.init()
    node = Node('ev_talker')
    pub = node.create_publisher(String, 'ev', QoSProfile(depth=10, deadline=Duration(seconds=0.1)))
    if 'lossy' in sys.argv:  # the network drops every third sample after it was stamped
        put, sent = pub._put, [0]
        def lossy(payload, **kwargs):
            sent[0] += 1
            if sent[0] % 3:
                put(payload, **kwargs)
        pub._put = lossy
    pub.wait_for_subscribers(1, timeout_sec=10)
    for i in range(9):
        pub.publish(String(data=str(i)))
        time.sleep(0.03)
    print('published', flush=True)
    time.sleep(60)
''')


class Events:
    """Records event payloads by kind, from the executor thread."""

    def __init__(self) -> None:
        self.seen: dict[str, list] = {}
        self._lock = threading.Lock()

    def __getattr__(self, kind: str):
        if kind.startswith('_'):
            raise AttributeError(kind)

        def record(info) -> None:
            with self._lock:
                self.seen.setdefault(kind, []).append(info)
        return record

    def of(self, kind: str) -> list:
        with self._lock:
            return list(self.seen.get(kind, []))


@pytest.fixture
def spinning(context):
    node = Node('ev_test', context=context)
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(node)
    thread = threading.Thread(target=lambda: _spin(executor), daemon=True)
    thread.start()
    yield node
    executor.shutdown()
    thread.join(timeout=5)


def _spin(executor) -> None:
    try:
        executor.spin()
    except Exception:  # noqa: BLE001 - ends with the context
        pass


def test_subscription_deadline_liveliness_and_matched_from_a_real_publisher(spinning, spawn, wait_for):
    from interfaces.std_msgs.msg import String
    from zros.qos_event import SubscriptionEventCallbacks as HumbleName
    assert HumbleName is SubscriptionEventCallbacks
    events, received = Events(), []
    callbacks = SubscriptionEventCallbacks(deadline=events.deadline, liveliness=events.liveliness,
                                           matched=events.matched, message_lost=events.lost)
    spinning.create_subscription(String, 'ev', received.append, QoSProfile(depth=10, deadline=Duration(seconds=0.25)),
                                 event_callbacks=callbacks)
    talker = spawn.script(PUBLISHER, name='ev_talker')
    wait_for(lambda: events.of('matched'), timeout=15, message='the publisher to match')
    assert events.of('matched')[0] == (1, 1, 1, 1)
    assert events.of('liveliness')[0] == (1, 0, 1, 0)  # alive, not_alive, alive change, not_alive change
    talker.wait_for_output('published', timeout=10)
    wait_for(lambda: len(received) == 9, message='the nine messages')
    assert not events.of('deadline'), 'no deadline is missed while messages come every 30 ms'
    wait_for(lambda: events.of('deadline'), timeout=3, message='a missed deadline once the publisher is quiet')
    missed = events.of('deadline')[0]
    assert (missed.total_count, missed.total_count_change) == (1, 1)
    talker.signal(signal.SIGKILL)  # the process dies: Zenoh drops its liveliness tokens
    wait_for(lambda: len(events.of('liveliness')) >= 2, timeout=5, message='liveliness to change')
    assert events.of('liveliness')[-1] == (0, 0, -1, 0)
    assert events.of('matched')[-1] == (1, 0, 0, -1)
    assert not events.of('lost')


def test_message_lost_counts_the_gaps(spinning, spawn, wait_for):
    from interfaces.std_msgs.msg import String
    events, received = Events(), []
    sub = spinning.create_subscription(String, 'ev', received.append, 10,
                                       event_callbacks=SubscriptionEventCallbacks(message_lost=events.lost))
    spawn.script(PUBLISHER, 'lossy', name='lossy_talker').wait_for_output('published', timeout=15)
    wait_for(lambda: len(received) == 6, message='the six messages that got through')
    assert [m.data for m in received] == ['0', '1', '3', '4', '6', '7']
    # The last drop leaves no gap behind it: a loss shows when a later message arrives.
    wait_for(lambda: sum(e.total_count_change for e in events.of('lost')) == 2, message='two lost messages')
    assert events.of('lost')[-1].total_count == sub.lost == 2


SUBSCRIBER = textwrap.dedent('''
    import zros
    from zros.node import Node
    from interfaces.std_msgs.msg import String

    zros.init()
    node = Node('ev_listener')
    node.create_subscription(String, 'ev', lambda msg: None, 10)  # reliable: our publisher is best effort
    zros.spin(node)
''')


def test_publisher_events_deadline_liveliness_incompatible_and_matched(spinning, spawn, wait_for):
    from interfaces.std_msgs.msg import String
    events = Events()
    qos = QoSProfile(depth=10, reliability=ReliabilityPolicy.BEST_EFFORT, deadline=Duration(seconds=0.2),
                     liveliness=LivelinessPolicy.MANUAL_BY_TOPIC, liveliness_lease_duration=Duration(seconds=0.3))
    callbacks = PublisherEventCallbacks(deadline=events.deadline, liveliness=events.liveliness,
                                        incompatible_qos=events.incompatible, matched=events.matched)
    pub = spinning.create_publisher(String, 'ev', qos, event_callbacks=callbacks)
    listener = spawn.script(SUBSCRIBER, name='ev_listener')
    wait_for(lambda: events.of('incompatible') and events.of('matched'), timeout=15, message='the listener')
    assert events.of('incompatible')[0].last_policy_kind == QoSPolicyKind.RELIABILITY
    assert events.of('matched')[0].current_count == 1
    assert 'incompatible QoS' in listener.wait_for_output('offering incompatible QoS', timeout=5)
    for _ in range(3):
        pub.publish(String(data='x'))
    wait_for(lambda: events.of('deadline') and events.of('liveliness'), timeout=3, message='deadline and lease')
    assert events.of('liveliness')[0] == (1, 1)
    pub.assert_liveliness()  # alive again; the lease lapses again
    wait_for(lambda: len(events.of('liveliness')) == 2, timeout=3, message='a second lapse')
    assert events.of('liveliness')[1].total_count == 2


def test_default_callbacks_warn_and_can_be_turned_off(spinning, spawn, wait_for):
    from interfaces.std_msgs.msg import String
    import zros.logging as zlog
    lines = []

    def sink(severity, name, message, *rest):
        lines.append(message)
    zlog.add_sink(sink)
    try:
        spinning.create_publisher(String, 'ev', QoSProfile(depth=1, reliability=ReliabilityPolicy.BEST_EFFORT))
        spinning.create_publisher(String, 'ev', QoSProfile(depth=1, reliability=ReliabilityPolicy.BEST_EFFORT),
                                  event_callbacks=PublisherEventCallbacks(use_default_callbacks=False))
        spawn.script(SUBSCRIBER, name='ev_listener')
        wait_for(lambda: any('requesting incompatible QoS' in line for line in lines), timeout=15,
                 message='the default warning')
        assert sum('requesting incompatible QoS' in line for line in lines) == 1, lines
        assert 'RELIABILITY (subscription /ev_listener;' in next(x for x in lines if 'incompatible' in x)
    finally:
        zlog.remove_sink(sink)


def test_an_endpoint_of_another_type_fires_incompatible_type_once_and_warns_by_default(spinning, wait_for):
    from interfaces.std_msgs.msg import Int32, String
    import zros.logging as zlog
    lines = []

    def sink(severity, name, message, *rest):
        lines.append(message)
    zlog.add_sink(sink)
    try:
        events = Events()
        pub = spinning.create_publisher(String, 'mixed', 10)
        assert len(pub.event_handlers) == 2      # the default incompatible QoS and type warnings
        sub = spinning.create_subscription(Int32, 'mixed', lambda m: None, 10, event_callbacks=SubscriptionEventCallbacks(
            incompatible_type=events.incompatible_type, use_default_callbacks=False))
        assert len(sub.event_handlers) == 1
        wait_for(lambda: events.of('incompatible_type'), timeout=10, message='the String publisher')
        assert events.of('incompatible_type')[0].total_count == 1
        wait_for(lambda: any("Incompatible type on topic '/mixed'" in line for line in lines), timeout=10,
                 message="the publisher's default warning")
        spinning.create_publisher(String, 'unrelated', 10)          # another graph change
        assert spinning.context.graph.wait_for(lambda es: any(e.name == '/unrelated' for e in es), 5.0)
        assert len(events.of('incompatible_type')) == 1
    finally:
        zlog.remove_sink(sink)


# -- overrides ----------------------------------------------------------------------------------
def test_qos_overrides_read_from_parameters_at_creation(context, tmp_path):
    from interfaces.std_msgs.msg import String
    from zros.parameter import Parameter
    params = tmp_path / 'qos.yaml'
    params.write_text(textwrap.dedent('''
        qos_node:
          ros__parameters:
            qos_overrides:
              /chatter:
                publisher:
                  reliability: best_effort
                  depth: 3
                  deadline: 500000000
    '''))
    node = Node('qos_node', context=context, cli_args=['--params-file', str(params)],
                parameter_overrides=[Parameter('qos_overrides./chatter.subscription_fast.history', value='keep_all')])
    options = QoSOverridingOptions([QoSPolicyKind.RELIABILITY, QoSPolicyKind.DEPTH, QoSPolicyKind.DEADLINE,
                                    QoSPolicyKind.DURABILITY])
    pub = node.create_publisher(String, 'chatter', 10, qos_overriding_options=options)
    assert pub.qos_profile.reliability == ReliabilityPolicy.BEST_EFFORT and pub.qos_profile.depth == 3
    assert pub.qos_profile.deadline.nanoseconds == 500_000_000
    assert node.get_parameter('qos_overrides./chatter.publisher.durability').value == 'volatile'
    assert node.describe_parameter('qos_overrides./chatter.publisher.depth').read_only
    assert node.count_publishers('chatter') == 1
    graph_qos = node.get_publishers_info_by_topic('/chatter')[0].qos_profile
    assert (graph_qos.reliability, graph_qos.depth) == (ReliabilityPolicy.BEST_EFFORT, 3)
    sub = node.create_subscription(String, 'chatter', lambda m: None, 10,
                                   qos_overriding_options=QoSOverridingOptions.with_default_policies(entity_id='fast'))
    assert sub.qos_profile.history.name == 'KEEP_ALL'
    plain = node.create_publisher(String, 'other', 10)
    assert not node.has_parameter('qos_overrides./other.publisher.depth') and plain.qos_profile.depth == 10


def test_qos_override_errors_are_clear(context):
    from interfaces.std_msgs.msg import String
    from zros.parameter import Parameter
    node = Node('qos_bad', context=context,
                parameter_overrides=[Parameter('qos_overrides./a.publisher.reliability', value='sometimes')])
    with pytest.raises(InvalidQosOverridesError, match="'sometimes' is not one of reliable, best_effort"):
        node.create_publisher(String, 'a', 10, qos_overriding_options=QoSOverridingOptions.with_default_policies())

    def at_most_five(qos):
        return QosCallbackResult(successful=qos.depth <= 5, reason='depth must be at most 5')
    with pytest.raises(InvalidQosOverridesError, match='depth must be at most 5'):
        node.create_publisher(String, 'b', 10, qos_overriding_options=QoSOverridingOptions(
            [QoSPolicyKind.DEPTH], callback=at_most_five))
