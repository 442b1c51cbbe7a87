"""launch_ros.descriptions: `ComposableNode` and the parameter descriptions."""
from __future__ import annotations

from zros.launch.files import module_getattr
from zros.launch.parameters import Parameter, ParameterFile, ParameterValue
from zros.launch_ros.descriptions.composable_node import ComposableNode

__all__ = ['ComposableNode', 'Parameter', 'ParameterFile', 'ParameterValue']

__getattr__ = module_getattr(__name__)
