"""Which actions the graph holds (rclpy.action.graph's functions).

Action servers and clients each declare one graph token of their own (docs/protocol.md), so
these are plain views over the node's copy of the graph, as the node's topic and service
listings are; rclpy reads the same from rcl's action graph.
"""
from __future__ import annotations

from typing import TYPE_CHECKING

from zros.graph import EntityKind, names_and_types

if TYPE_CHECKING:
    from zros.node import Node

__all__ = ['get_action_client_names_and_types_by_node', 'get_action_server_names_and_types_by_node',
           'get_action_names_and_types']


def get_action_client_names_and_types_by_node(node: 'Node', remote_node_name: str,
                                              remote_node_namespace: str) -> list[tuple[str, list[str]]]:
    """The actions one node has clients of.

    :param node: The node whose view of the graph is read.
    :param remote_node_name: The name of the node asked about, without namespace.
    :param remote_node_namespace: That node's namespace.
    :return: ``(action, [type, ...])`` pairs, sorted by action name.
    """
    return node._by_node(EntityKind.ACTION_CLIENT, remote_node_name, remote_node_namespace)


def get_action_server_names_and_types_by_node(node: 'Node', remote_node_name: str,
                                              remote_node_namespace: str) -> list[tuple[str, list[str]]]:
    """The actions one node serves; the arguments and result are get_action_client_names_and_types_by_node's."""
    return node._by_node(EntityKind.ACTION_SERVER, remote_node_name, remote_node_namespace)


def get_action_names_and_types(node: 'Node') -> list[tuple[str, list[str]]]:
    """Every action that has a server or a client in the graph.

    :param node: The node whose view of the graph is read.
    :return: ``(action, [type, ...])`` pairs, sorted by action name.
    """
    return names_and_types(node._graph_entities(), (EntityKind.ACTION_SERVER, EntityKind.ACTION_CLIENT))
