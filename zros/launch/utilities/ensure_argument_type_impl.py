"""launch.utilities.ensure_argument_type: the check launch's constructors run on each argument,
so a wrong type fails where the action is built with the argument's and the caller's name."""
from __future__ import annotations

from collections.abc import Iterable
from typing import Any

__all__ = ['ensure_argument_type']


def ensure_argument_type(argument: Any, types: type | Iterable[type], argument_name: str,
                         caller: str | None = None) -> None:
    """Check that `argument` is an instance of one of `types`.

    Args:
        argument: the value to check.
        types: one class, or an iterable of classes.
        argument_name: named in the error.
        caller: the function or class that was given the argument, named in the error.

    Raises:
        TypeError: `argument` matches none of `types`, or the check itself was called wrongly.
    """
    if not isinstance(types, (type, Iterable)):
        raise TypeError(f"ensure_argument_type(): 'types' must be a type or an iterable of types, "
                        f'got {types!r} of type {type(types).__name__}')
    if not isinstance(argument_name, str):
        raise TypeError(f"ensure_argument_type(): 'argument_name' must be a str, got {type(argument_name).__name__}")
    if caller is not None and not isinstance(caller, str):
        raise TypeError(f"ensure_argument_type(): 'caller' must be a str or None, got {type(caller).__name__}")
    candidates = [types] if isinstance(types, type) else list(types)
    if any(isinstance(kind, type) and isinstance(argument, kind) for kind in candidates):
        return
    who = f"'{caller}': e" if caller is not None else 'E'
    names = ', '.join(getattr(kind, '__name__', str(kind)) for kind in candidates)
    raise TypeError(f"{who}xpected '{argument_name}' to be one of [{names}], "
                    f'got {argument!r} of type {type(argument).__name__}')
