"""`rclpy.impl.implementation_singleton`: a porting shim for the exception types rclpy code reaches
through `_rclpy`.

In rclpy, `rclpy_implementation` is the C extension, and Python code and tests import it mostly
to name its exceptions (`except _rclpy.RCLError`, `pytest.raises(_rclpy.UnknownROSArgsError)`).
zros has no C layer: `rclpy_implementation` here is a namespace of zros's own exception classes,
the ones zros raises in those cases, so such code catches what zros raises. It holds no handles,
wait sets or C QoS structs; code that needs those tests rclpy's C layer, not its behaviour.
"""
from __future__ import annotations

from types import SimpleNamespace

from zros.arguments import RosArgsError, UnknownRosArgsError
from zros.errors import RCLError
from zros.exceptions import InvalidHandle

__all__ = ['rclpy_implementation']

rclpy_implementation = SimpleNamespace(
    # a request the current state refuses (an unavailable lifecycle transition ...)
    RCLError=RCLError,
    # a malformed `--ros-args` section, and one with arguments ROS does not know
    RCLInvalidROSArgsError=RosArgsError,
    UnknownROSArgsError=UnknownRosArgsError,
    # an entity used after it was destroyed
    InvalidHandle=InvalidHandle,
)
