"""launch_ros.descriptions: `ComposableNode` and the parameter descriptions."""
from __future__ import annotations

from zros.launch.actions.composable import ComposableNode
from zros.launch.files import module_getattr
from zros.launch.parameters import Parameter, ParameterFile, ParameterValue

__all__ = ['ComposableNode', 'Parameter', 'ParameterFile', 'ParameterValue']

__getattr__ = module_getattr(__name__)
