"""Events of a launch (launch.events): `Shutdown`, `IncludeLaunchDescription`,
`ExecutionComplete`, the process events in `launch.events.process`, and `matches_action` to aim
an event at one action (launch_ros's lifecycle `ChangeState` takes it as its
`lifecycle_node_matcher`)."""
from __future__ import annotations

from zros.launch.events.execution_complete import ExecutionComplete
from zros.launch.events.include_launch_description import IncludeLaunchDescription
from zros.launch.events.matchers import ActionMatcher, matches_action
from zros.launch.events.shutdown import Shutdown
from zros.launch.files import module_getattr

from zros.launch.events import process  # noqa: E402,F401  (launch.events.process.X)

__all__ = ['Shutdown', 'IncludeLaunchDescription', 'ExecutionComplete', 'matches_action', 'ActionMatcher',
           'process']

__getattr__ = module_getattr(__name__)
