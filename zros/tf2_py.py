"""tf2_py: tf2's core in Python (`BufferCore` and tf2's exceptions), as ROS's C extension
offers it; zros's frame tree is plain Python already, so this names it under tf2_py's module."""
from __future__ import annotations

from zros.tf2_ros.buffer_core import BufferCore
from zros.tf2_ros.exceptions import (ConnectivityException, ExtrapolationException, InvalidArgumentException,
                                     LookupException, TimeoutException, TransformException)

__all__ = ['BufferCore', 'TransformException', 'LookupException', 'ConnectivityException',
           'ExtrapolationException', 'InvalidArgumentException', 'TimeoutException']
