"""Event handlers (launch.event_handlers): what to do when a process starts, prints or exits,
an action completes, or the launch shuts down; one module per handler, as in launch.

`RegisterEventHandler(OnProcessExit(target_action=node, on_exit=[...]))`. Under `zros launch`
the handler's actions are resolved with the rest of the launch (so their errors stop it before
anything starts) and carried out by the supervisor when the event happens; `on_exit` /
`on_start` may instead be a function `f(event, context)` returning actions, run when the event
happens, with the launch.events.process event (`event.returncode`, `event.pid`, `event.action`,
`event.process_name`, `event.cmd`). Any handler can also be registered on a running launch's
context (`context.register_event_handler`), and is then offered every event of its queue.
"""
from __future__ import annotations

from zros.launch.event_handlers.on_action_event_base import OnActionEventBase
from zros.launch.event_handlers.on_execution_complete import OnExecutionComplete
from zros.launch.event_handlers.on_include_launch_description import OnIncludeLaunchDescription
from zros.launch.event_handlers.on_process_exit import OnProcessExit
from zros.launch.event_handlers.on_process_io import OnProcessIO
from zros.launch.event_handlers.on_process_start import OnProcessStart
from zros.launch.event_handlers.on_shutdown import OnShutdown
from zros.launch.files import module_getattr

__all__ = ['OnProcessStart', 'OnProcessExit', 'OnProcessIO', 'OnShutdown', 'OnExecutionComplete',
           'OnIncludeLaunchDescription', 'OnActionEventBase']

__getattr__ = module_getattr(__name__)
