"""zros.graph_content: the hidden-name rule and rqt_graph's content, on plain graph records."""
from __future__ import annotations

import pytest

from zros.graph import Entity, EntityKind
from zros.graph_content import graph_content, is_hidden


def _node(name: str) -> Entity:
    return Entity(EntityKind.NODE, 'z1', 1, 0, '/', name)


def _endpoint(kind: str, node: str, topic: str) -> Entity:
    return Entity(kind, 'z1', 1, 1, '/', node, topic, 'std_msgs/msg/String')


@pytest.mark.parametrize('name, hidden', [('/talker', False), ('/_zros_cli', True), ('/a/_private/b', True),
                                          ('/ns/topic_', False), ('/', False)])
def test_a_name_is_hidden_when_a_part_starts_with_an_underscore(name, hidden):
    assert is_hidden(name) is hidden


def test_graph_content_leaves_hidden_and_debug_out_unless_asked():
    entities = [_node('talker'), _node('listener'), _node('_cli'),
                _endpoint(EntityKind.PUBLISHER, 'talker', '/chatter'),
                _endpoint(EntityKind.SUBSCRIPTION, 'listener', '/chatter'),
                _endpoint(EntityKind.PUBLISHER, 'talker', '/rosout'),
                _endpoint(EntityKind.SUBSCRIPTION, '_cli', '/chatter')]
    shown = graph_content(entities)
    assert shown == {'nodes': ['/listener', '/talker'], 'topics': {'/chatter': ['std_msgs/msg/String']},
                     'edges': [('n:/talker', 't:/chatter'), ('t:/chatter', 'n:/listener')]}
    everything = graph_content(iter(entities), include_hidden=True, include_debug=True)
    assert everything['nodes'] == ['/_cli', '/listener', '/talker']
    assert set(everything['topics']) == {'/chatter', '/rosout'}
    assert ('t:/chatter', 'n:/_cli') in everything['edges']
