"""rclpy.utilities equivalents."""
from __future__ import annotations

from zros.arguments import remove_ros_args
from zros.context import get_default_context

__all__ = ['remove_ros_args', 'ok', 'get_default_context']


def ok() -> bool:
    return get_default_context().ok()
