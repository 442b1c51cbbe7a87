"""tf2's exceptions, with ROS's names and meanings (tf2_py's, re-exported by tf2_ros).

All derive from TransformException, which is a ZrosError, so the CLI prints them as one line.
"""
from __future__ import annotations

from zros.errors import ZrosError

__all__ = ['TransformException', 'LookupException', 'ConnectivityException', 'ExtrapolationException',
           'InvalidArgumentException', 'TimeoutException']


class TransformException(ZrosError):
    """Base of every tf2 failure: catch this one to handle them all."""


class LookupException(TransformException):
    """A frame named in a lookup is not known to the buffer."""


class ConnectivityException(TransformException):
    """Both frames are known but belong to different trees."""


class ExtrapolationException(TransformException):
    """The requested time lies outside the data buffered for some link of the chain."""


class InvalidArgumentException(TransformException):
    """A malformed argument: an empty frame id, a NaN, a quaternion that is no rotation."""


class TimeoutException(TransformException):
    """A wait for a transform ran out of time."""
