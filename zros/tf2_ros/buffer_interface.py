"""tf2_ros.BufferInterface: transforming stamped messages, for anything that can look transforms
up (the local Buffer, and BufferClient, which asks a buffer server)."""
from __future__ import annotations

from typing import Any

from zros.tf2_ros.exceptions import TransformException

__all__ = ['BufferInterface']


class BufferInterface:
    """Needs `lookup_transform` and `lookup_transform_full` of the class it is mixed into."""

    def lookup_transform(self, target_frame: str, source_frame: str, time: Any, timeout: Any = None) -> Any:
        raise NotImplementedError

    def lookup_transform_full(self, target_frame: str, target_time: Any, source_frame: str, source_time: Any,
                              fixed_frame: str, timeout: Any = None) -> Any:
        raise NotImplementedError

    def transform(self, object_stamped: Any, target_frame: str, timeout: Any = None, new_type: Any = None) -> Any:
        """`object_stamped` (PointStamped, PoseStamped, Vector3Stamped, PoseWithCovarianceStamped,
        PolygonStamped, ...) expressed in `target_frame`, at its own stamp.

        :param object_stamped: a stamped geometry message.
        :param target_frame: the frame to express it in.
        :param timeout: how long to wait for the transform (a Duration; None: don't wait).
        :param new_type: the message type wanted back; only the input's own type is supported.
        :return: a new message of the same type.
        :raises TransformException: (a subclass of it) when the transform is not available.
        """
        from zros.tf2_ros.geometry import do_transform
        transform = self.lookup_transform(target_frame, object_stamped.header.frame_id,
                                          object_stamped.header.stamp, timeout)
        return _convert(do_transform(object_stamped, transform), new_type)

    def transform_full(self, object_stamped: Any, target_frame: str, target_time: Any, fixed_frame: str,
                       timeout: Any = None, new_type: Any = None) -> Any:
        """Express a stamped message in `target_frame` at `target_time`, through `fixed_frame`.

        :param object_stamped: a stamped geometry message (PointStamped, PoseStamped, ...).
        :param target_frame: the frame to express it in.
        :param target_time: the time of the target frame.
        :param fixed_frame: a frame that does not move between the two times.
        :param timeout: how long to wait for the transform (None: don't wait).
        :param new_type: the message type wanted back; only the input's own type is supported.
        :return: a new message of the same type, in `target_frame`.
        :raises TransformException: (a subclass of it) when the transform is not available.
        """
        from zros.tf2_ros.geometry import do_transform
        transform = self.lookup_transform_full(target_frame, target_time, object_stamped.header.frame_id,
                                               object_stamped.header.stamp, fixed_frame, timeout)
        return _convert(do_transform(object_stamped, transform), new_type)


def _convert(msg: Any, new_type: Any) -> Any:
    if new_type is None or isinstance(msg, new_type):
        return msg
    raise TransformException(f'cannot convert {type(msg).__name__} to {getattr(new_type, "__name__", new_type)}')
