"""Errors of the launch system.

Every problem in a launch file is reported as one line that starts with where it is, so an
editor can jump to it: `file:line: <tag>: <key>: reason`. Problems found while the launch runs
(a process that cannot be started) are `LaunchError`s without a location.
"""
from __future__ import annotations

from typing import NamedTuple

from zros.errors import ZrosError

__all__ = ['LaunchError', 'LaunchFileError', 'LaunchTypeError', 'ParameterTypeError', 'SubstitutionError', 'ExpressionNameError',
           'LaunchFileNotFoundError', 'Origin']


class LaunchError(ZrosError, RuntimeError):
    """A launch cannot go on: bad command line, bad file, or a process that cannot start.

    Also a RuntimeError, because launch raises RuntimeError for these and user code catches it."""


class SubstitutionError(LaunchError):
    """A substitution cannot be parsed or evaluated; the caller adds where it was written."""


class ExpressionNameError(SubstitutionError, NameError):
    """A `$(eval)` / PythonExpression uses a name not in its scope (a module not listed); also
    a NameError, which is what launch's PythonExpression raises."""


class Origin(NamedTuple):
    """Where something was written: file, 1-based line, the tag and (optionally) the key."""

    path: str
    line: int
    tag: str
    key: str | None = None

    def __str__(self) -> str:
        where = f'{self.path}:{self.line}: {self.tag}'
        return f'{where}: {self.key}' if self.key else where

    def with_key(self, key: str | None, line: int | None = None) -> 'Origin':
        return Origin(self.path, self.line if line is None else line, self.tag, key)

    def error(self, reason: str) -> 'LaunchFileError':
        return LaunchFileError(self, reason)


class LaunchFileError(LaunchError, ValueError):
    """A launch file is wrong; str() is `file:line: <tag>: <key>: reason` on one line.

    Also a ValueError, which is what launch's front ends raise for a wrong attribute or child.
    """

    def __init__(self, origin: Origin | None, reason: str) -> None:
        self.origin = origin
        self.reason = ' '.join(str(reason).split()) if '\n' in str(reason) else str(reason)
        super().__init__(f'{origin}: {self.reason}' if origin is not None else self.reason)


class LaunchFileNotFoundError(LaunchFileError, FileNotFoundError):
    """A launch file (or a file it reads) is not there; also a FileNotFoundError, which is what
    launch raises for it."""


class ParameterTypeError(LaunchFileError, TypeError):
    """A node parameter's value cannot be a ROS parameter (a mixed or nested list); also a
    TypeError, which is what launch_ros raises for it."""


class LaunchTypeError(LaunchFileError, TypeError):
    """A launch class was given a value of the wrong kind (a target that is not an action, a
    handler that is neither actions nor a function). Also a TypeError, since launch raises
    that and launch code catches it."""
