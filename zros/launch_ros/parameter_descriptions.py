"""launch_ros.parameter_descriptions: `ParameterValue`, `ParameterFile`, `Parameter`."""
from __future__ import annotations

from zros.launch.files import module_getattr
from zros.launch.parameters import Parameter, ParameterFile, ParameterValue

__all__ = ['Parameter', 'ParameterFile', 'ParameterValue']

__getattr__ = module_getattr(__name__)
