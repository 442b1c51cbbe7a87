"""Checks that a class is an interface type (rclpy.type_support).

rclpy's generated classes load their C type support on first use, and these checks import it
and say whether a class is a message or a service. A zros interface class carries its codec
from the moment typesupport builds it, so there is nothing to import for one; the checks keep
rclpy's contract for the rest (a class that declares an empty `_TYPE_SUPPORT`, such as one
generated for rclpy, still gets its metaclass's `__import_type_support__` call).
"""
from __future__ import annotations

from typing import Any

from zros.exceptions import NoTypeSupportImportedException

__all__ = ['check_for_type_support', 'check_is_valid_msg_type', 'check_is_valid_srv_type',
           'is_message_type', 'is_service_type']


def is_message_type(msg_type: Any) -> bool:
    """Whether `msg_type` is a zros message class (built from a .msg, or a service's or an
    action's parts)."""
    return isinstance(msg_type, type) and hasattr(msg_type, '_ENC')


def is_service_type(srv_type: Any) -> bool:
    """Whether `srv_type` holds a Request and a Response class, as a service type does."""
    return isinstance(srv_type, type) and hasattr(srv_type, 'Request') and hasattr(srv_type, 'Response')


def check_for_type_support(msg_or_srv_type: Any) -> None:
    """Make sure the type can be used on the wire.

    Raises:
        AttributeError: it is no interface type at all (no type support slot; a ROS 1 class).
        NoTypeSupportImportedException: it declares type support but none could be imported.
    """
    if hasattr(msg_or_srv_type, '_TYPE') and hasattr(msg_or_srv_type, '_HASH'):
        return   # a zros message, service or action class (or an instance): its codec came with it
    meta = msg_or_srv_type.__class__
    try:
        support = meta._TYPE_SUPPORT
    except AttributeError as exc:
        raise AttributeError(f'{msg_or_srv_type!r} is no ROS 2 interface type (it has no type support): '
                             'this might be a ROS 1 message type') from exc
    if support is None:
        meta.__import_type_support__()
    if meta._TYPE_SUPPORT is None:
        raise NoTypeSupportImportedException()


def check_is_valid_msg_type(msg_type: Any) -> None:
    """Raise RuntimeError unless `msg_type` is a message type (a service or action is not)."""
    check_for_type_support(msg_type)
    if not is_message_type(msg_type):
        raise RuntimeError(f'The message type provided is not valid ({msg_type!r}): this might be a service '
                           'or action')


def check_is_valid_srv_type(srv_type: Any) -> None:
    """Raise RuntimeError unless `srv_type` is a service type (a message or action is not)."""
    check_for_type_support(srv_type)
    if not is_service_type(srv_type):
        raise RuntimeError(f'The service type provided is not valid ({srv_type!r}): this might be a message '
                           'or action')
