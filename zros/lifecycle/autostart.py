"""Whether a node that is a lifecycle node in Jazzy but a plain node in Humble (slam_toolbox)
brings itself up, or waits in `unconfigured` for someone to drive it.

Both shapes of launch file run the same executable: Humble's `Node(...)` expects it to work at
once, Jazzy's `LifecycleNode(...)` followed by `EmitEvent(ChangeState(...))` (or a lifecycle
manager with `use_lifecycle_manager: true`) expects it to wait. The launch tells the node which
by setting `ZROS_LIFECYCLE_LAUNCH=1` in the environment of every process a LifecycleNode action
starts (ROS's launch passes nothing: there the executable itself differs between the two
distributions).
"""
from __future__ import annotations

import os
from typing import Mapping

__all__ = ['LIFECYCLE_LAUNCH_ENV', 'waits_for_transitions']

#: Set to '1' by the launch's LifecycleNode action in the environment of the process it starts.
LIFECYCLE_LAUNCH_ENV = 'ZROS_LIFECYCLE_LAUNCH'


def waits_for_transitions(*, use_lifecycle_manager: bool, env: Mapping[str, str] | None = None) -> bool:
    """True when the node must wait unconfigured for transitions: a LifecycleNode action started
    it, or its `use_lifecycle_manager` parameter says a lifecycle manager will. Otherwise it
    configures and activates itself (autostart)."""
    env = os.environ if env is None else env
    return use_lifecycle_manager or env.get(LIFECYCLE_LAUNCH_ENV, '') == '1'
