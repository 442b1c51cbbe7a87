"""Errors raised by zros.

One base class, so that a user (or the CLI) can catch every zros failure in one place and
print it as a one-line message instead of a traceback.
"""
from __future__ import annotations

from typing import Iterable

__all__ = [
    'ZrosError',
    'InvalidNameError',
    'InterfaceError',
    'InterfaceParseError',
    'InterfaceNotFoundError',
    'MessageTypeError',
    'DecodeError',
    'NotInitializedError',
    'RCLError',
    'CliError',
    'ServiceCallError',
    'InvalidHandle',
    'with_suggestion',
]


class ZrosError(Exception):
    """Base of every error zros raises on purpose."""


class InvalidNameError(ZrosError, ValueError):
    """A topic, node, namespace or service name breaks the ROS 2 naming rules."""


# rclpy's one class per kind of name (rclpy.exceptions); each is an InvalidNameError.
class InvalidNodeNameException(InvalidNameError):
    """A node name breaks the rules."""


class InvalidNamespaceException(InvalidNameError):
    """A namespace breaks the rules."""


class InvalidTopicNameException(InvalidNameError):
    """A topic name breaks the rules."""


class InvalidServiceNameException(InvalidNameError):
    """A service (or action) name breaks the rules."""


class InterfaceError(ZrosError):
    """An interface (.msg/.srv/.action) cannot be loaded or used."""


class InterfaceParseError(InterfaceError):
    """An interface file has a syntax error; the message starts with `file:line:`."""


class InterfaceNotFoundError(InterfaceError, ImportError):
    """No interface of that name exists on the interface search path."""


class MessageTypeError(ZrosError, TypeError):
    """A message field got a value of the wrong type; the message names the field."""


class DecodeError(ZrosError):
    """A payload could not be decoded as the expected message type."""


class NotInitializedError(ZrosError, RuntimeError):
    """An operation needs `zros.init()` to have been called first."""


class RCLError(ZrosError, RuntimeError):
    """A request ROS refuses: a lifecycle transition the current state does not offer, a domain id
    out of range... (rclpy raises `_rclpy.RCLError`, a RuntimeError, in these cases; hence the name)."""


class CliError(ZrosError):
    """A command-line failure the user can fix; the CLI prints it as one line and exits 1."""


class ServiceCallError(ZrosError):
    """A service call failed: the server raised, refused the request, or did not answer."""


def with_suggestion(message: str, word: str, choices: Iterable[str], *, otherwise: str = '') -> str:
    """`message`, followed by ". Did you mean 'x'?" with the choice closest to the mistyped
    `word` (difflib's ratio of at least 0.6), or by `otherwise` when none is that close: the
    error a typo gets, in one line."""
    import difflib
    close = difflib.get_close_matches(word, list(choices), n=1)
    return f"{message}. Did you mean '{close[0]}'?" if close else message + otherwise


class InvalidHandle(ZrosError):
    """An entity (node, publisher, timer ...) was used through its `handle` after it was destroyed
    (rclpy.exceptions.InvalidHandle)."""
