"""The six services through which any node's parameters are read and changed remotely.

Named as in ROS 2 (`<node>/list_parameters`, `get_parameters`, `get_parameter_types`,
`set_parameters`, `set_parameters_atomically`, `describe_parameters`) with the rcl_interfaces
types, so `zros param` and any ROS-style client talk to them the same way.
"""
from __future__ import annotations

from typing import TYPE_CHECKING, Any

from zros.exceptions import ParameterException, ParameterNotDeclaredException, ParameterUninitializedException
from zros.parameter import Parameter
from zros.qos import qos_profile_parameters

if TYPE_CHECKING:
    from zros.node import Node

__all__ = ['ParameterService', 'PARAMETER_SERVICES']

PARAMETER_SERVICES = ('describe_parameters', 'get_parameters', 'get_parameter_types', 'list_parameters',
                      'set_parameters', 'set_parameters_atomically')
#: The largest request a parameter service reads (thousands of names): every node has these
#: services, and a flood of names would stall the node's executor while it is answered.
PARAMETER_REQUEST_LIMIT = 64 << 10


class ParameterService:
    def __init__(self, node: 'Node') -> None:
        from interfaces.rcl_interfaces import srv
        self._node = node
        store = node._parameters
        self._store = store
        fq = node.get_fully_qualified_name()
        self.services = [node.create_service(srv_type, f'{fq}/{name}', callback, qos_profile=qos_profile_parameters)
                         for srv_type, name, callback in (
                             (srv.DescribeParameters, 'describe_parameters', self._describe),
                             (srv.GetParameters, 'get_parameters', self._get),
                             (srv.GetParameterTypes, 'get_parameter_types', self._get_types),
                             (srv.ListParameters, 'list_parameters', self._list),
                             (srv.SetParameters, 'set_parameters', self._set),
                             (srv.SetParametersAtomically, 'set_parameters_atomically', self._set_atomically))]
        for service in self.services:
            service.max_request_size = min(service.max_request_size, PARAMETER_REQUEST_LIMIT)

    def _describe(self, request: Any, response: Any) -> Any:
        from interfaces.rcl_interfaces.msg import ParameterDescriptor
        out = []
        for name in request.names:
            try:
                out.append(self._store.describe(name))
            except ParameterException:
                out.append(ParameterDescriptor(name=name))
        response.descriptors = out
        return response

    def _get(self, request: Any, response: Any) -> Any:
        """All the values asked for, or none (an empty list, as rclpy answers) when one of the
        names is undeclared or declared with a type but no value yet."""
        try:
            response.values = [self._store.get(name).get_parameter_value() for name in request.names]
        except (ParameterNotDeclaredException, ParameterUninitializedException):
            response.values = []
        return response

    def _get_types(self, request: Any, response: Any) -> Any:
        response.types = [int(self._store.get_or(name).type_) for name in request.names]
        return response

    def _list(self, request: Any, response: Any) -> Any:
        names, prefixes = self._store.list(list(request.prefixes), int(request.depth))
        response.result.names = names
        response.result.prefixes = prefixes
        return response

    def _set(self, request: Any, response: Any) -> Any:
        response.results = [self._store.set_atomically([Parameter.from_parameter_msg(p)])
                            for p in request.parameters]
        return response

    def _set_atomically(self, request: Any, response: Any) -> Any:
        response.result = self._store.set_atomically([Parameter.from_parameter_msg(p) for p in request.parameters])
        return response
