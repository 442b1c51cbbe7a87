"""The stack actions: `PushLaunchConfigurations` / `PopLaunchConfigurations`,
`PushEnvironment` / `PopEnvironment`, `ResetEnvironment`.

A scope in launch is not a feature of the actions that have one: a group (or a timer, or an
event handler) returns its children between a push and a pop, and resolution visits them in
order. These are those pushes and pops, usable on their own in a launch file too. The ROS scope
(pushed namespace, `SetParameter`, `SetRemap`) is launch_ros's part of the launch
configurations, so it is saved and restored with them.
"""
from __future__ import annotations

from typing import Any

from zros.launch.action import Action, launch_tag
from zros.launch.errors import Origin

__all__ = ['PushLaunchConfigurations', 'PopLaunchConfigurations', 'PushEnvironment', 'PopEnvironment',
           'ResetEnvironment', 'scoped']


class PushLaunchConfigurations(Action):
    """Save the launch configurations (and the ROS scope) for a later `PopLaunchConfigurations`."""

    def execute(self, context: Any) -> None:
        context.push_launch_configurations()


class PopLaunchConfigurations(Action):
    """Restore the launch configurations saved by the matching `PushLaunchConfigurations`."""

    def execute(self, context: Any) -> None:
        context.pop_launch_configurations()


class PushEnvironment(Action):
    """Save the environment for a later `PopEnvironment`."""

    def execute(self, context: Any) -> None:
        context.push_environment()


class PopEnvironment(Action):
    """Restore the environment saved by the matching `PushEnvironment`."""

    def execute(self, context: Any) -> None:
        context.pop_environment()


@launch_tag('reset_env')
class ResetEnvironment(Action):
    """`ResetEnvironment()`; YAML `reset_env: {}`: back to the environment the launch started
    with (what `group` with `forwarding: false` does first). Not scoped by itself."""


def _reset_environment(self: ResetEnvironment, context: Any) -> None:
    context.reset_environment()


ResetEnvironment.execute = _reset_environment  # type: ignore[method-assign]


def scoped(actions: list[Action], origin: Origin, *, first: list[Action] | None = None) -> list[Action]:
    """`actions` between pushes and pops of the configurations and environment, with `first`
    (resets, sets) inside the scope before them: the order launch's GroupAction returns."""
    return [PushLaunchConfigurations(origin=origin), PushEnvironment(origin=origin), *(first or []),
            *actions, PopEnvironment(origin=origin), PopLaunchConfigurations(origin=origin)]
