"""launch_ros.actions.set_parameters_from_file: launch_ros's module path of
`SetParametersFromFile`, which zros keeps with the other scope actions in
zros.launch.actions.ros (so importing it from here gives the one class)."""
from __future__ import annotations

from zros.launch.actions.ros import SetParametersFromFile

__all__ = ['SetParametersFromFile']
