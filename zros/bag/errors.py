"""The one error type of zros.bag."""
from __future__ import annotations

from zros.errors import ZrosError

__all__ = ['BagError']


class BagError(ZrosError):
    """A bag cannot be written or read (missing, not MCAP, truncated, output exists, ...)."""
