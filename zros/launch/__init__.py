"""zros launch: run many nodes from one launch file, Python, YAML or XML, supervised.

A Python launch file is ROS 2's with `zros.` in front of the imports
(`from zros.launch import LaunchDescription`, `from zros.launch_ros.actions import Node`); a
YAML one is ROS 2's YAML format. Both build the same actions (zros.launch.actions), so they
resolve, print and run identically. Two stages, kept apart so a launch never half-starts:
1. `resolve(path, launch_arguments=...)` loads the file (zros.launch.files), evaluates
   substitutions and conditions, follows includes and returns a `Plan` of processes, log
   messages, timers, event handlers and shutdowns; any problem is a `LaunchFileError` reading
   `file:line: <tag>: <key>: reason`.
2. `Supervisor(plan).run()` (zros.launch.supervisor) starts and watches the processes:
   prefixed output, per-run log directory, respawn, event handlers, `on_exit: shutdown`, and
   SIGINT -> SIGTERM -> SIGKILL escalation with no orphans.
"""
from __future__ import annotations

from zros.launch.action import Action
from zros.launch.conditions import Condition
from zros.launch.context import LaunchContext
from zros.launch.description import declared_arguments, parse_launch_arguments, resolve
from zros.launch.errors import LaunchError, LaunchFileError, Origin, SubstitutionError
from zros.launch.event import Event
from zros.launch.event_handler import BaseEventHandler, EventHandler
from zros.launch.files import module_getattr
from zros.launch.launch_description import LaunchDescription
from zros.launch.launch_description_entity import LaunchDescriptionEntity, SomeEntitiesType_types_tuple
from zros.launch.launch_description_sources import LaunchDescriptionSource
from zros.launch.launch_service import LaunchService
from zros.launch.plan import Plan, ProcessSpec
from zros.launch.template import Substitution

# `import zros.launch` then `zros.launch.actions.X`, as ROS 2 launch files write it.
from zros.launch import (actions, conditions, event_handlers, events,  # noqa: E402,F401
                         launch_description_sources, substitutions)

__all__ = [
    'LaunchDescription', 'LaunchDescriptionEntity', 'LaunchContext', 'LaunchDescriptionSource', 'Action', 'Condition', 'Substitution',
    'SomeSubstitutionsType', 'resolve', 'declared_arguments', 'parse_launch_arguments', 'Plan', 'ProcessSpec',
    'LaunchError', 'LaunchFileError', 'SubstitutionError', 'Origin', 'actions', 'conditions', 'event_handlers',
    'events', 'launch_description_sources', 'substitutions', 'LaunchService', 'Event', 'EventHandler',
    'BaseEventHandler', 'LaunchDescriptionEntity', 'SomeEntitiesType_types_tuple',
]

#: launch's name for "a string, a Substitution, or a list of them" (for type hints).
SomeSubstitutionsType = object

__getattr__ = module_getattr(__name__)
