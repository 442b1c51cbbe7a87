"""Launch actions (launch.actions), one class per construct and per YAML tag.

`from zros.launch.actions import DeclareLaunchArgument, IncludeLaunchDescription, ...` in a
Python launch file builds the same objects the YAML front end builds from `arg`, `include`, ...
The ROS-specific actions (`Node`, `PushRosNamespace`, ...) are in zros.launch_ros.actions.
Each class can also be imported from launch's own module for it (`launch.actions.execute_process`):
those modules are thin re-exports of the modules here.
"""
from __future__ import annotations

from zros.launch.actions.arg import (DeclareLaunchArgument, ResetLaunchConfigurations, SetLaunchConfiguration,
                                     UnsetLaunchConfiguration)
from zros.launch.actions.env import AppendEnvironmentVariable, SetEnvironmentVariable, UnsetEnvironmentVariable
from zros.launch.actions.events import RegisterEventHandler, UnregisterEventHandler
from zros.launch.actions.execute_local import ExecuteLocal
from zros.launch.actions.group import GroupAction
from zros.launch.actions.include import IncludeLaunchDescription
from zros.launch.actions.log import LogInfo
from zros.launch.actions.opaque import OpaqueFunction
from zros.launch.actions.process import ExecuteProcess
from zros.launch.actions.scope import (PopEnvironment, PopLaunchConfigurations, PushEnvironment,
                                       PushLaunchConfigurations, ResetEnvironment)
from zros.launch.actions.shutdown import EmitEvent, Shutdown
from zros.launch.actions.timer import TimerAction
from zros.launch.files import module_getattr

# Modules whose tags only zros.launch_ros exports; imported so that YAML knows their tags.
from zros.launch.actions import composable as _composable, ros as _ros  # noqa: F401

__all__ = [
    'AppendEnvironmentVariable', 'DeclareLaunchArgument', 'EmitEvent', 'ExecuteLocal', 'ExecuteProcess', 'GroupAction',
    'IncludeLaunchDescription', 'LogInfo', 'OpaqueFunction', 'PopEnvironment', 'PopLaunchConfigurations',
    'PushEnvironment', 'PushLaunchConfigurations', 'RegisterEventHandler', 'ResetEnvironment',
    'ResetLaunchConfigurations', 'SetEnvironmentVariable', 'SetLaunchConfiguration', 'Shutdown',
    'TimerAction', 'UnregisterEventHandler', 'UnsetEnvironmentVariable', 'UnsetLaunchConfiguration',
]

__getattr__ = module_getattr(__name__)
