"""AsyncParameterClient (rclpy.parameter_client): another node's parameters through its six
parameter services, each call returning a Future of the service's Response.

    client = AsyncParameterClient(node, 'turtlesim')
    future = client.set_parameters([Parameter('background_r', value=50)])
    zros.spin_until_future_complete(node, future)
    future.result().results[0].successful
"""
from __future__ import annotations

from typing import TYPE_CHECKING, Any, Callable, Sequence

from zros.graph import EntityKind
from zros.parameter import Parameter, parameter_dict_from_yaml_file
from zros.qos import QoSProfile, qos_profile_parameter_events, qos_profile_services_default

if TYPE_CHECKING:
    from zros.node import Node
    from zros.subscription import Subscription
    from zros.task import Future

__all__ = ['AsyncParameterClient']

_SERVICES = ('describe_parameters', 'get_parameters', 'get_parameter_types', 'list_parameters',
             'set_parameters', 'set_parameters_atomically')


class AsyncParameterClient:
    """Clients of `remote_node_name`'s parameter services (a relative name is resolved in the
    namespace of `node`, as every service name is)."""

    def __init__(self, node: 'Node', remote_node_name: str, qos_profile: QoSProfile = qos_profile_services_default,
                 callback_group: Any = None) -> None:
        from interfaces.rcl_interfaces import srv
        self.node = node
        self.remote_node_name = remote_node_name
        types = {'describe_parameters': srv.DescribeParameters, 'get_parameters': srv.GetParameters,
                 'get_parameter_types': srv.GetParameterTypes, 'list_parameters': srv.ListParameters,
                 'set_parameters': srv.SetParameters, 'set_parameters_atomically': srv.SetParametersAtomically}
        self._clients = {name: node.create_client(types[name], f'{remote_node_name}/{name}', qos_profile=qos_profile,
                                                  callback_group=callback_group) for name in _SERVICES}

    def services_are_ready(self) -> bool:
        return all(client.service_is_ready() for client in self._clients.values())

    def wait_for_services(self, timeout_sec: float | None = None) -> bool:
        """Wait (on graph changes) until all six services exist; False on timeout."""
        names = {client.srv_name for client in self._clients.values()}
        return self.node.context.graph.wait_for(
            lambda entities: names <= {e.name for e in entities if e.kind == EntityKind.SERVICE}, timeout_sec)

    def _call(self, service: str, request: Any, callback: Callable | None) -> 'Future':
        future = self._clients[service].call_async(request)
        if callback is not None:
            future.add_done_callback(callback)
        return future

    def _request(self, service: str, **fields: Any) -> Any:
        return self._clients[service].srv_type.Request(**fields)

    def list_parameters(self, prefixes: list[str] | None = None, depth: int | None = None,
                        callback: Callable | None = None) -> 'Future':
        return self._call('list_parameters', self._request('list_parameters', prefixes=list(prefixes or []),
                                                           depth=depth or 0), callback)

    def get_parameters(self, names: list[str], callback: Callable | None = None) -> 'Future':
        return self._call('get_parameters', self._request('get_parameters', names=list(names)), callback)

    def get_parameter_types(self, names: list[str], callback: Callable | None = None) -> 'Future':
        return self._call('get_parameter_types', self._request('get_parameter_types', names=list(names)), callback)

    def describe_parameters(self, names: list[str], callback: Callable | None = None) -> 'Future':
        return self._call('describe_parameters', self._request('describe_parameters', names=list(names)), callback)

    def set_parameters(self, parameters: Sequence[Any], callback: Callable | None = None) -> 'Future':
        """`parameters`: zros Parameters or rcl_interfaces/msg/Parameter messages."""
        return self._call('set_parameters', self._request('set_parameters', parameters=_messages(parameters)),
                          callback)

    def set_parameters_atomically(self, parameters: Sequence[Any], callback: Callable | None = None) -> 'Future':
        return self._call('set_parameters_atomically',
                          self._request('set_parameters_atomically', parameters=_messages(parameters)), callback)

    def delete_parameters(self, names: list[str], callback: Callable | None = None) -> 'Future':
        """Unset `names` (only dynamically typed parameters can be): a set to NOT_SET."""
        return self.set_parameters([Parameter(name) for name in names], callback)

    def load_parameter_file(self, parameter_file: str, use_wildcard: bool = False,
                            callback: Callable | None = None) -> 'Future':
        """Set the parameters of a ROS 2 parameter YAML file on the remote node: as rclpy, those
        of every node entry in the file, whatever its name (`/**` too with use_wildcard)."""
        return self.set_parameters(self._from_file(parameter_file, use_wildcard), callback)

    def load_parameter_file_atomically(self, parameter_file: str, use_wildcard: bool = False,
                                       callback: Callable | None = None) -> 'Future':
        return self.set_parameters_atomically(self._from_file(parameter_file, use_wildcard), callback)

    def _from_file(self, path: str, use_wildcard: bool) -> list[Any]:
        return list(parameter_dict_from_yaml_file(path, use_wildcard).values())

    def on_parameter_event(self, callback: Callable, qos_profile: QoSProfile = qos_profile_parameter_events,
                           **kwargs: Any) -> 'Subscription':
        """Subscribe to /parameter_events (every node's parameter changes)."""
        from interfaces.rcl_interfaces.msg import ParameterEvent
        return self.node.create_subscription(ParameterEvent, '/parameter_events', callback, qos_profile, **kwargs)

    def destroy(self) -> None:
        for client in self._clients.values():
            self.node.destroy_client(client)
        self._clients.clear()


def _messages(parameters: Sequence[Any]) -> list[Any]:
    return [p.to_parameter_msg() if isinstance(p, Parameter) else p for p in parameters]
