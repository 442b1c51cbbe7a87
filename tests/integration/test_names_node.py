"""Name resolution seen from a live node: remapping rules applied by a node in its own Zenoh
session (the pure rules: tests/unit/test_names.py)."""
from __future__ import annotations

import pytest

from zros.errors import InvalidNameError


def test_node_resolves_names_with_remapping(context):
    from zros.node import Node
    node = Node('talker', context=context, namespace='robot',
                cli_args=['--ros-args', '-r', 'chatter:=news', '-r', 'talker:~/x:=/abs', '-r', 'listener:a:=b'])
    assert node.get_namespace() == '/robot'
    assert node.get_fully_qualified_name() == '/robot/talker'
    assert node.resolve_topic_name('chatter') == '/robot/news'
    assert node.resolve_topic_name('chatter', only_expand=True) == '/robot/chatter'
    assert node.resolve_topic_name('~/x') == '/abs'
    assert node.resolve_topic_name('a') == '/robot/a'
    with pytest.raises(InvalidNameError):
        node.create_publisher(__import__('interfaces.std_msgs.msg', fromlist=['String']).String, 'a*b', 10)
    renamed = Node('talker', context=context, cli_args=['--ros-args', '-r', '__node:=x', '-r', '__ns:=/ns'])
    assert renamed.get_fully_qualified_name() == '/ns/x'
    with pytest.raises(InvalidNameError):
        Node('1bad', context=context)
