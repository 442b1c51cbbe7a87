"""Events an action can emit (launch.events): zros's launch has `Shutdown`."""
from __future__ import annotations

from typing import Any

from zros.launch.files import module_getattr

__all__ = ['Shutdown']

__getattr__ = module_getattr(__name__)


class Shutdown:
    """`EmitEvent(event=Shutdown(reason='...'))` stops the whole launch."""

    def __init__(self, *, reason: Any = None) -> None:
        self.reason = reason

    def __repr__(self) -> str:
        return f'<Shutdown reason={self.reason!r}>'
