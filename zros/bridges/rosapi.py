"""rosapi: the graph and the parameters as services under /rosapi, for rosbridge clients.

A web page has no graph API of its own: roslib's `ros.getTopics()`, `getNodes()`, `getServices()`,
`getTopicType()` and its `Param` class call these services through the bridge, as they do on
ROS 2 with rosbridge_suite's rosapi node. Parameter names are `<node>:<parameter>` and values
JSON text, as there (`/talker:use_sim_time` -> "false"). The node is `nodes/rosapi/rosapi_node.py`.
"""
from __future__ import annotations

import json
import os
from typing import TYPE_CHECKING, Any

from zros.graph import EntityKind, endpoints, names_and_types
from zros.parameter import Parameter, parameter_value_to_python

if TYPE_CHECKING:
    from zros.node import Node

__all__ = ['Rosapi', 'PARAMETER_TIMEOUT']

PARAMETER_TIMEOUT = 5.0   # [s] for another node's parameter services to answer
_TOPIC_KINDS = (EntityKind.PUBLISHER, EntityKind.SUBSCRIPTION)


class Rosapi:
    """The /rosapi services on `node`, which a MultiThreadedExecutor spins (the parameter services
    wait for other nodes' answers inside their callbacks)."""

    def __init__(self, node: 'Node') -> None:
        from interfaces.rosapi_msgs import srv
        from zros.callback_groups import ReentrantCallbackGroup
        self.node = node
        group = ReentrantCallbackGroup()
        services = {
            'topics': (srv.Topics, self.topics), 'topics_for_type': (srv.TopicsForType, self.topics_for_type),
            'services': (srv.Services, self.services), 'nodes': (srv.Nodes, self.nodes),
            'node_details': (srv.NodeDetails, self.node_details),
            'action_servers': (srv.GetActionServers, self.action_servers),
            'topic_type': (srv.TopicType, self.topic_type), 'service_type': (srv.ServiceType, self.service_type),
            'publishers': (srv.Publishers, self.publishers), 'subscribers': (srv.Subscribers, self.subscribers),
            'get_param': (srv.GetParam, self.get_param), 'set_param': (srv.SetParam, self.set_param),
            'has_param': (srv.HasParam, self.has_param), 'get_param_names': (srv.GetParamNames, self.get_param_names),
            'get_time': (srv.GetTime, self.get_time), 'get_ros_version': (srv.GetROSVersion, self.get_ros_version),
        }
        for name, (srv_type, callback) in services.items():
            node.create_service(srv_type, f'/rosapi/{name}', callback, callback_group=group)

    def _entities(self) -> list:
        return self.node.context.graph.entities()

    # -- graph ---------------------------------------------------------------------------------
    def topics(self, _request: Any, response: Any) -> Any:
        pairs = names_and_types(self._entities(), _TOPIC_KINDS)
        response.topics = [name for name, _ in pairs]
        response.types = [types[0] for _, types in pairs]
        return response

    def topics_for_type(self, request: Any, response: Any) -> Any:
        response.topics = [name for name, types in names_and_types(self._entities(), _TOPIC_KINDS)
                           if request.type in types]
        return response

    def services(self, _request: Any, response: Any) -> Any:
        response.services = [name for name, _ in names_and_types(self._entities(), (EntityKind.SERVICE,))]
        return response

    def nodes(self, _request: Any, response: Any) -> Any:
        response.nodes = self.node.get_fully_qualified_node_names()
        return response

    def node_details(self, request: Any, response: Any) -> Any:
        mine = [e for e in self._entities() if e.node_fqn == request.node]
        response.subscribing = sorted({e.name for e in mine if e.kind == EntityKind.SUBSCRIPTION})
        response.publishing = sorted({e.name for e in mine if e.kind == EntityKind.PUBLISHER})
        response.services = sorted({e.name for e in mine if e.kind == EntityKind.SERVICE})
        return response

    def action_servers(self, _request: Any, response: Any) -> Any:
        response.action_servers = [name for name, _ in names_and_types(self._entities(), (EntityKind.ACTION_SERVER,))]
        return response

    def topic_type(self, request: Any, response: Any) -> Any:
        types = dict(names_and_types(self._entities(), _TOPIC_KINDS)).get(request.topic)
        response.type = types[0] if types else ''
        return response

    def service_type(self, request: Any, response: Any) -> Any:
        types = dict(names_and_types(self._entities(), (EntityKind.SERVICE,))).get(request.service)
        response.type = types[0] if types else ''
        return response

    def publishers(self, request: Any, response: Any) -> Any:
        response.publishers = sorted({e.node_fqn for e in endpoints(self._entities(), EntityKind.PUBLISHER,
                                                                     request.topic)})
        return response

    def subscribers(self, request: Any, response: Any) -> Any:
        response.subscribers = sorted({e.node_fqn for e in endpoints(self._entities(), EntityKind.SUBSCRIPTION,
                                                                      request.topic)})
        return response

    # -- parameters ----------------------------------------------------------------------------
    def get_param(self, request: Any, response: Any) -> Any:
        """The value as JSON text; the default (or null) when the node or parameter is missing."""
        node_name, name = _split_parameter_name(request.name)
        value = _json_or_text(request.default_value) if request.default_value else None
        answer = self._call_parameters(node_name, 'get_parameters', names=[name])
        if answer is not None and answer.values and answer.values[0].type != Parameter.Type.NOT_SET:
            value = parameter_value_to_python(answer.values[0])
        response.value = json.dumps(value.tolist() if hasattr(value, 'tolist') else value)
        return response

    def set_param(self, request: Any, response: Any) -> Any:
        node_name, name = _split_parameter_name(request.name)
        value = _json_or_text(request.value)
        self._call_parameters(node_name, 'set_parameters', parameters=[Parameter(name, value=value).to_parameter_msg()])
        return response

    def has_param(self, request: Any, response: Any) -> Any:
        node_name, name = _split_parameter_name(request.name)
        answer = self._call_parameters(node_name, 'get_parameters', names=[name])
        response.exists = bool(answer is not None and answer.values
                               and answer.values[0].type != Parameter.Type.NOT_SET)
        return response

    def get_param_names(self, _request: Any, response: Any) -> Any:
        names = []
        for node_name in self.node.get_fully_qualified_node_names():
            answer = self._call_parameters(node_name, 'list_parameters', prefixes=[], depth=0)
            if answer is not None:
                names += [f'{node_name}:{name}' for name in answer.result.names]
        response.names = names
        return response

    def _call_parameters(self, node_name: str, service: str, **fields: Any) -> Any:
        """Another node's parameter service answered, or None (no such node, no answer in time)."""
        from interfaces.rcl_interfaces import srv
        srv_type = {'get_parameters': srv.GetParameters, 'set_parameters': srv.SetParameters,
                    'list_parameters': srv.ListParameters}[service]
        name = f'{node_name}/{service}'
        if not any(e.kind == EntityKind.SERVICE and e.name == name for e in self._entities()):
            return None
        client = self.node.create_client(srv_type, name)
        try:
            future = client.call_async(srv_type.Request(**fields), timeout_sec=PARAMETER_TIMEOUT)
            if not future.wait(PARAMETER_TIMEOUT + 1.0) or future.exception() is not None:
                return None
            return future.result()
        finally:
            self.node.destroy_client(client)

    # -- time ----------------------------------------------------------------------------------
    def get_time(self, _request: Any, response: Any) -> Any:
        response.time = self.node.get_clock().now().to_msg()
        return response

    def get_ros_version(self, _request: Any, response: Any) -> Any:
        response.version = 2
        response.distro = os.environ.get('ROS_DISTRO') or 'humble'
        return response


def _split_parameter_name(text: str) -> tuple[str, str]:
    """'/talker:use_sim_time' -> ('/talker', 'use_sim_time'); a bare 'talker' gets its slash."""
    node_name, sep, name = text.partition(':')
    if not sep or not node_name or not name:
        from zros.errors import ZrosError
        raise ZrosError(f"malformed parameter name '{text}': expecting <node_name>:<param_name>")
    return ('' if node_name.startswith('/') else '/') + node_name, name


def _json_or_text(text: str) -> Any:
    try:
        return json.loads(text)
    except ValueError:
        return text
