"""launch_ros.actions: `Node` and the actions that set what later nodes get."""
from __future__ import annotations

from zros.launch.actions.composable import ComposableNodeContainer, LoadComposableNodes
from zros.launch.actions.group import PushRosNamespace
from zros.launch.actions.process import Node
from zros.launch.actions.ros import SetParameter, SetRemap, SetUseSimTime
from zros.launch.files import module_getattr
from zros.launch.lifecycle import LifecycleNode

__all__ = ['Node', 'LifecycleNode', 'PushRosNamespace', 'PushROSNamespace', 'SetParameter', 'SetRemap',
           'SetUseSimTime', 'ComposableNodeContainer', 'LoadComposableNodes']

__getattr__ = module_getattr(__name__)

#: launch_ros's newer spelling.
PushROSNamespace = PushRosNamespace

