"""Where a Python launch object was written: the first stack frame outside zros's launch code.

A YAML entity knows its file and line from the loader; a Python action, condition or
description learns them here when it is constructed, so an error found later while resolving
still reads `my.launch.py:12: Node: package: ...`, as YAML errors do.
"""
from __future__ import annotations

import os
import sys

from zros.launch.errors import Origin

__all__ = ['origin_here']

_ZROS = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
_INTERNAL = tuple(os.path.join(_ZROS, package, '') for package in ('launch', 'launch_ros'))


def origin_here(tag: str) -> Origin:
    """The file and line of the nearest caller outside zros.launch / zros.launch_ros."""
    frame = sys._getframe(1)
    while frame is not None and frame.f_code.co_filename.startswith(_INTERNAL):
        frame = frame.f_back
    if frame is None:
        return Origin('<python>', 0, tag)
    return Origin(frame.f_code.co_filename, frame.f_lineno, tag)
