"""The `start_type_description_service` parameter every rclpy node declares
(rclpy.type_description_service).

In ROS 2 it switches rcl's ~/get_type_description service on. zros declares the parameter, read
only and true by default as rclpy does, so that code and tools listing a node's parameters see
the same set; the service itself is not served (type hashes travel in the graph instead, see
docs/porting.md).
"""
from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from zros.node import Node

__all__ = ['START_TYPE_DESCRIPTION_SERVICE_PARAM', 'TypeDescriptionService']

START_TYPE_DESCRIPTION_SERVICE_PARAM = 'start_type_description_service'


class TypeDescriptionService:
    """Declares `start_type_description_service` on a node; made by Node, not by users.

    :param node: The node to declare it on (unless it is declared already).
    """

    def __init__(self, node: 'Node') -> None:
        from interfaces.rcl_interfaces.msg import ParameterDescriptor, ParameterType
        if not node.has_parameter(START_TYPE_DESCRIPTION_SERVICE_PARAM):
            node.declare_parameter(START_TYPE_DESCRIPTION_SERVICE_PARAM, True, ParameterDescriptor(
                name=START_TYPE_DESCRIPTION_SERVICE_PARAM, type=ParameterType.PARAMETER_BOOL,
                description='If enabled, start the ~/get_type_description service.', read_only=True))
        value = node.get_parameter(START_TYPE_DESCRIPTION_SERVICE_PARAM).value
        #: What the parameter asks for (the service is not served either way).
        self.enabled = value is True

    def destroy(self) -> None:
        """Nothing to release: no service is declared."""
