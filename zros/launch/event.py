"""`Event` (launch.Event): what a launch's event queue carries, the base of launch.events.

Handlers (launch.EventHandler) pick events by a matcher, usually an isinstance test, so an
event is plain data with a `name` saying what it is.
"""
from __future__ import annotations

__all__ = ['Event']


class Event:
    """Base class of launch events; subclasses set `name` to their dotted class name."""

    name = 'launch.Event'
