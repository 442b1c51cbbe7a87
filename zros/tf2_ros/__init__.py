"""zros.tf2_ros: ROS 2's tf2_ros Python API (Buffer, TransformListener, broadcasters, tf2's
exceptions) on zros.

    from zros.tf2_ros import Buffer, TransformListener, TransformBroadcaster, TransformException

As in ROS, `Duration` and `Time` are importable from here (course code does
`from tf2_ros import Duration`). The frame tree itself is `buffer_core.BufferCore`, plain
Python with no transport; `listener_hub` is the one place TF messages come in from Zenoh.
"""
from __future__ import annotations

from zros.duration import Duration
from zros.tf2_ros.buffer import Buffer
from zros.tf2_ros.buffer_core import BufferCore
from zros.tf2_ros.exceptions import (ConnectivityException, ExtrapolationException, InvalidArgumentException,
                                     LookupException, TimeoutException, TransformException)
from zros.tf2_ros.static_transform_broadcaster import StaticTransformBroadcaster
from zros.tf2_ros.transform_broadcaster import TransformBroadcaster
from zros.tf2_ros.transform_listener import TransformListener
from zros.time import Time

__all__ = ['Buffer', 'BufferCore', 'TransformListener', 'TransformBroadcaster', 'StaticTransformBroadcaster',
           'TransformException', 'LookupException', 'ConnectivityException', 'ExtrapolationException',
           'InvalidArgumentException', 'TimeoutException', 'Duration', 'Time']
