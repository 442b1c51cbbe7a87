"""launch_ros.actions.node: launch_ros's module path of `Node`, which zros keeps in
zros.launch.actions.process (so importing it from here gives the one class)."""
from __future__ import annotations

from zros.launch.actions.process import Node

__all__ = ['Node']
