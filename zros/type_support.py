"""rclpy.type_support's check, for code that validates an interface type before using it.

rclpy loads a C type support per type and fails here when a type's library is missing or it
is a ROS 1 type. zros reads interfaces from IDL files at import time (docs/architecture.md §4),
so a class zros made is always supported; what is left to check is that the object is such a
class (or an instance of one).
"""
from __future__ import annotations

from typing import Any

__all__ = ['check_for_type_support']


def check_for_type_support(msg_or_srv_type: Any) -> None:
    """Check that `msg_or_srv_type` is a zros message, service or action type (or instance).

    Raises:
        AttributeError: it is not one (rclpy raises the same for a type without type support).
    """
    if not isinstance(getattr(msg_or_srv_type, '_TYPE', None), str):
        raise AttributeError(f'{msg_or_srv_type!r} has no type support: not a ROS 2 interface type '
                             '(import it from <package>.msg, .srv or .action)')
