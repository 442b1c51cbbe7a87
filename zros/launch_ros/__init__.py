"""zros's launch_ros: the ROS-specific launch actions, substitutions and descriptions.

`from launch_ros.actions import Node` becomes `from zros.launch_ros.actions import Node`. The
classes are zros.launch's own (the YAML `node`, `push_ros_namespace`, ... tags build them too).
"""
from __future__ import annotations

from zros.launch_ros import actions, descriptions, event_handlers, events, parameter_descriptions, substitutions

__all__ = ['actions', 'descriptions', 'event_handlers', 'events', 'parameter_descriptions', 'substitutions']
