"""zros launch: run many nodes from one ROS 2 YAML launch file, supervised.

Two stages, kept apart so a launch never half-starts:
1. `resolve(path, launch_arguments=...)` parses the file (zros.launch.entity, one action class
   per tag in zros.launch.actions), evaluates substitutions and conditions, follows includes
   and returns a `Plan` of processes, log messages, timers and shutdowns; any problem is a
   `LaunchFileError` reading `file:line: <tag>: <key>: reason`.
2. `Supervisor(plan).run()` (zros.launch.supervisor) starts and watches the processes:
   prefixed output, per-run log directory, respawn, `on_exit: shutdown`, and SIGINT ->
   SIGTERM -> SIGKILL escalation with no orphans.
"""
from __future__ import annotations

from zros.launch.description import declared_arguments, parse_launch_arguments, resolve
from zros.launch.errors import LaunchError, LaunchFileError, Origin, SubstitutionError
from zros.launch.plan import Plan, ProcessSpec

__all__ = [
    'resolve', 'declared_arguments', 'parse_launch_arguments', 'Plan', 'ProcessSpec',
    'LaunchError', 'LaunchFileError', 'SubstitutionError', 'Origin',
]
