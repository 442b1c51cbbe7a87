"""Stopping a child process together with everything it started.

The launch supervisor, zros.testing and the headless browser start children in their own
session (`start_new_session=True`), so a child's process group holds its whole tree; this
module is the one place that ends such a group. It sits low in the layers so the launch
supervisor need not import the test helpers for it.
"""
from __future__ import annotations

import os
import signal
import subprocess

__all__ = ['kill_group']


def kill_group(popen: subprocess.Popen) -> None:
    """SIGKILL a process and its process group, and reap it (waiting up to 5 s)."""
    try:
        os.killpg(popen.pid, signal.SIGKILL)
    except (ProcessLookupError, PermissionError):
        pass
    try:
        popen.wait(timeout=5)
    except subprocess.TimeoutExpired:  # pragma: no cover - SIGKILL does not fail
        pass
