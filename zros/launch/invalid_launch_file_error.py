"""launch.invalid_launch_file_error: the error of a launch file no front end can read.

zros reads a file by its name (`.py`, `.xml` / `.launch`, `.yaml` / `.yml`); a file with any
other name is tried as YAML and then as XML, and when both fail this error lists why each did.
"""
from __future__ import annotations

from typing import Sequence

from zros.launch.errors import LaunchFileError

__all__ = ['InvalidLaunchFileError']


class InvalidLaunchFileError(LaunchFileError):
    """No front end could read the file; str() names each front end's exception and its type.

    Args:
        extension: the file's extension (or the formats tried), for the message.
        likely_errors: the exceptions the front ends raised, most likely first.
    """

    def __init__(self, extension: str = '', *, likely_errors: Sequence[BaseException] | None = None) -> None:
        self.extension = extension
        self.likely_errors = list(likely_errors or [])
        if not extension or not self.likely_errors:
            reason = 'the launch file may have a syntax error, or its format is unknown'
        else:
            causes = '; '.join(f'{type(error).__name__}: {error}' for error in self.likely_errors)
            reason = f'cannot load a file of format [{extension}]: {causes}'
        super().__init__(None, reason)
