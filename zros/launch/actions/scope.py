"""The stack actions: `PushLaunchConfigurations` / `PopLaunchConfigurations`,
`PushEnvironment` / `PopEnvironment`, `ResetEnvironment`.

A scope in launch is not a feature of the actions that have one: a group (or a timer, or an
event handler) returns its children between a push and a pop, and resolution visits them in
order. These are those pushes and pops, usable on their own in a launch file too. The ROS scope
(pushed namespace, `SetParameter`, `SetRemap`) is launch_ros's part of the launch
configurations, so it is saved and restored with them.
"""
from __future__ import annotations

import re
from typing import Any

from zros.launch.action import Action, launch_tag
from zros.launch.errors import Origin

__all__ = ['PushLaunchConfigurations', 'PopLaunchConfigurations', 'PushEnvironment', 'PopEnvironment',
           'ResetEnvironment', 'scoped']


class _ContextStep(Action):
    """An action that is one call of the `LaunchContext` method named like its class
    (`PushEnvironment` -> `push_environment`): the context owns the stacks."""

    def execute(self, context: Any) -> None:
        getattr(context, re.sub(r'(?<!^)(?=[A-Z])', '_', type(self).__name__).lower())()


class PushLaunchConfigurations(_ContextStep):
    """Save the launch configurations for a later `PopLaunchConfigurations`. The ROS scope
    (pushed namespace, `SetParameter`, `SetRemap`) is saved with them."""


class PopLaunchConfigurations(_ContextStep):
    """Restore what the matching `PushLaunchConfigurations` saved; configurations set since
    then are gone. Without a push before it, the launch fails."""


class PushEnvironment(_ContextStep):
    """Save the environment that later processes get, for a later `PopEnvironment`."""


class PopEnvironment(_ContextStep):
    """Restore the environment the matching `PushEnvironment` saved: variables set, changed
    or unset since then are as they were. Without a push before it, the launch fails."""


@launch_tag('reset_env')
class ResetEnvironment(_ContextStep):
    """`ResetEnvironment()`; YAML `reset_env: {}`: back to the environment the launch started
    with (what `group` with `forwarding: false` does first). Not scoped by itself."""


def scoped(actions: list[Action], origin: Origin, *, first: list[Action] | None = None) -> list[Action]:
    """`actions` between pushes and pops of the configurations and environment, with `first`
    (resets, sets) inside the scope before them: the order launch's GroupAction returns."""
    return [PushLaunchConfigurations(origin=origin), PushEnvironment(origin=origin), *(first or []),
            *actions, PopEnvironment(origin=origin), PopLaunchConfigurations(origin=origin)]
