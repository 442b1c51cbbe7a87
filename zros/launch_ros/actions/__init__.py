"""launch_ros.actions: `Node` and the actions that set what later nodes get.

One module per action, at launch_ros's module paths (`launch_ros.actions.node`, ...); each
re-exports the class zros.launch runs, so both import paths give the same class.
"""
from __future__ import annotations

from zros.launch.files import module_getattr
from zros.launch_ros.actions.composable_node_container import ComposableNodeContainer
from zros.launch_ros.actions.lifecycle_node import LifecycleNode
from zros.launch_ros.actions.lifecycle_transition import LifecycleTransition
from zros.launch_ros.actions.load_composable_nodes import LoadComposableNodes
from zros.launch_ros.actions.node import Node
from zros.launch_ros.actions.push_ros_namespace import PushROSNamespace, PushRosNamespace
from zros.launch_ros.actions.ros_timer import ROSTimer
from zros.launch_ros.actions.set_parameter import SetParameter
from zros.launch_ros.actions.set_parameters_from_file import SetParametersFromFile
from zros.launch_ros.actions.set_remap import SetRemap
from zros.launch_ros.actions.set_ros_log_dir import SetROSLogDir
from zros.launch_ros.actions.set_use_sim_time import SetUseSimTime

__all__ = ['Node', 'LifecycleNode', 'LifecycleTransition', 'PushRosNamespace', 'PushROSNamespace', 'SetParameter', 'SetParametersFromFile',
           'SetRemap', 'SetROSLogDir', 'SetUseSimTime', 'ROSTimer', 'ComposableNodeContainer', 'LoadComposableNodes']

__getattr__ = module_getattr(__name__)
