"""rclpy.type_support's checks, for code that validates an interface type before using it.

rclpy loads a C type support per type and fails here when a type's library is missing or it
is a ROS 1 type. zros reads interfaces from IDL files at import time (docs/architecture.md §4),
so a class zros made is always supported; what is left to check is that the object is such a
class (or an instance of one), and which kind it is. A class in rclpy's generated shape (its
metaclass holds `_TYPE_SUPPORT` and `__import_type_support__`) is checked as rclpy checks it.
"""
from __future__ import annotations

from typing import Any

from zros.exceptions import NoTypeSupportImportedException

__all__ = ['check_for_type_support', 'check_is_valid_msg_type', 'check_is_valid_srv_type']

_ABSENT = object()


def check_for_type_support(msg_or_srv_type: Any) -> None:
    """Check that `msg_or_srv_type` is a message, service or action type (or an instance).

    Raises:
        AttributeError: it is not one (as rclpy raises for a type without type support).
        NoTypeSupportImportedException: a type in rclpy's shape whose support did not load.
    """
    if isinstance(getattr(msg_or_srv_type, '_TYPE', None), str):
        return   # made by zros from its IDL file
    meta = type(msg_or_srv_type)
    if getattr(meta, '_TYPE_SUPPORT', _ABSENT) is _ABSENT:
        raise AttributeError(f'{msg_or_srv_type!r} has no type support: not a ROS 2 interface type '
                             '(import it from <package>.msg, .srv or .action)')
    if meta._TYPE_SUPPORT is None:
        meta.__import_type_support__()
        if meta._TYPE_SUPPORT is None:
            raise NoTypeSupportImportedException()


def check_is_valid_msg_type(msg_type: Any) -> None:
    """Check that `msg_type` is a message type, not a service or action.

    Raises:
        AttributeError: it is no interface type at all.
        RuntimeError: it is another kind of interface.
    """
    check_for_type_support(msg_type)
    if not hasattr(msg_type, '_ENC'):
        raise RuntimeError(f'The message type provided is not valid ({msg_type}), this might be a service '
                           'or action')


def check_is_valid_srv_type(srv_type: Any) -> None:
    """Check that `srv_type` is a service type (it has a Request and a Response).

    Raises:
        AttributeError: it is no interface type at all.
        RuntimeError: it is another kind of interface.
    """
    check_for_type_support(srv_type)
    if getattr(srv_type, 'Request', None) is None or getattr(srv_type, 'Response', None) is None:
        raise RuntimeError(f'The service type provided is not valid ({srv_type}), this might be a message '
                           'or action')
