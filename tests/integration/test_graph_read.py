"""Graph reads are bounded: they answer within their deadline, with many entities up, and say
when an answer is partial (issue 20, item 3)."""
from __future__ import annotations

import signal
import time

import pytest

from zros.graph import fetch_entities
from zros.node import Node

from interfaces.std_msgs.msg import String


def test_graph_reads_answer_with_hundreds_of_tokens(context, zros_cli):
    """More liveliness tokens than a Zenoh FIFO receiver holds (256) once froze every read."""
    node = Node('crowded', context=context)
    for index in range(300):
        node.create_publisher(String, f'crowd/topic_{index:03d}', 10)
    for args in (('node', 'list'), ('topic', 'list')):
        started = time.monotonic()
        result = zros_cli(*args, timeout=20)
        assert result.returncode == 0, result
        assert time.monotonic() - started < 15
    assert '/crowded' in zros_cli('node', 'list').stdout
    topics = zros_cli('topic', 'list').stdout.split()
    assert sum(t.startswith('/crowd/topic_') for t in topics) == 300


def test_a_read_without_a_hub_is_bounded_and_marked_partial(context):
    other_domain = context.domain_id + 1 if context.domain_id < 232 else context.domain_id - 1
    started = time.monotonic()
    entities = fetch_entities(context.session, other_domain, timeout=0.4)
    assert time.monotonic() - started < 1.5
    assert entities == [] and entities.complete is False


def test_a_read_from_the_hub_is_complete(context, make_context):
    Node('present', context=context)
    reader = make_context()
    entities = fetch_entities(reader.session, reader.domain_id, timeout=2.0)
    assert entities.complete
    assert any(e.node_fqn == '/present' for e in entities)


@pytest.mark.parametrize('signum', [signal.SIGINT, signal.SIGTERM], ids=['SIGINT', 'SIGTERM'])
def test_a_node_stopped_by_a_signal_leaves_the_graph(context, spawn, signum):
    """After a signal a node's entities are withdrawn by its session's close, not one by one;
    every one of them must still leave the graph of the processes that stay."""
    child = spawn.node('demo_nodes', 'talker')
    child.wait_for_output('Publishing', timeout=20)    # constructed and spinning

    def talker_entities(entities):
        return [e for e in entities if e.node_fqn == '/talker']
    assert context.graph.wait_for(lambda entities: any(e.name == '/chatter' for e in talker_entities(entities)), 10)
    child.signal(signum)
    assert child.wait(5) == 0, child.output()
    assert context.graph.wait_for(lambda entities: not talker_entities(entities), 5), \
        talker_entities(context.graph.entities())
    assert not talker_entities(fetch_entities(context.session, context.domain_id, timeout=2.0))
