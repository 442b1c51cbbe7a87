"""launch.utilities.class_tools_impl: `isinstance`/`issubclass` checks that accept either an
instance or a class, as launch's entity visitors ask "is this entity (or entity type) an X?"."""
from __future__ import annotations

import inspect
from typing import Any

__all__ = ['isclassinstance', 'is_a', 'is_a_subclass']


def isclassinstance(obj: Any) -> bool:
    """True for any object with a class, which in Python 3 is every object (kept for launch's API)."""
    return hasattr(obj, '__class__')


def is_a(obj: Any, entity_type: type) -> bool:
    """Whether `obj` is an instance of `entity_type` (or of a subclass).

    Raises:
        RuntimeError: `entity_type` is not a class (launch raises the same).
    """
    if not isclassinstance(obj):
        raise RuntimeError(f'{obj!r} is not an instance of a class')
    if not inspect.isclass(entity_type):
        raise RuntimeError(f'entity_type {entity_type!r} is not a class')
    return isinstance(obj, entity_type)


def is_a_subclass(obj: Any, entity_type: type) -> bool:
    """Whether `obj` is an instance of `entity_type`, or is itself a class derived from it."""
    if is_a(obj, entity_type):
        return True
    return inspect.isclass(obj) and issubclass(obj, entity_type)
