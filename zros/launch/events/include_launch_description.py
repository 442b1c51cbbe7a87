"""`IncludeLaunchDescription` (launch.events): asks the launch to visit a launch description.

`LaunchService.include_launch_description(ld)` queues it; the launch's own
OnIncludeLaunchDescription handler answers with the description, which is then visited.
"""
from __future__ import annotations

from typing import Any

from zros.launch.event import Event

__all__ = ['IncludeLaunchDescription']


class IncludeLaunchDescription(Event):
    """The event carrying `launch_description` into the running launch."""

    name = 'launch.events.IncludeLaunchDescription'

    def __init__(self, launch_description: Any) -> None:
        self.launch_description = launch_description

    def __repr__(self) -> str:
        return f'<IncludeLaunchDescription {self.launch_description!r}>'
