"""Launch locals: the names a launch context lends to the actions it runs (`context.locals`).

launch passes an event to the actions of its handler this way (`context.locals.event`), and
user code reads them by attribute. Globals stay for the whole launch; locals are pushed and
popped around the actions that should see them, and win over globals of the same name.
"""
from __future__ import annotations

from typing import Any

from zros.launch.errors import LaunchError

__all__ = ['LaunchLocals', 'LocalsView', 'pop_saved']


def pop_saved(stack: list, pop: str, push: str) -> Any:
    """The last state saved on `stack`; a `pop` without its `push` is the launch file's error."""
    if not stack:
        raise LaunchError(f'{pop} without a {push} before it')
    return stack.pop()


class LocalsView:
    """`context.locals`: read-only attribute access, naming what is there when a name is not."""

    def __init__(self, values: dict[str, Any]) -> None:
        object.__setattr__(self, '_values', values)

    def __getattr__(self, name: str) -> Any:
        values = object.__getattribute__(self, '_values')
        if name not in values:
            raise AttributeError(f"context.locals has no '{name}' (it has: {', '.join(values) or 'nothing'})")
        return values[name]

    def __setattr__(self, name: str, value: Any) -> None:
        raise AttributeError(f"context.locals is read-only: cannot set '{name}'")


class LaunchLocals:
    """Globals plus a stack of local scopes."""

    def __init__(self) -> None:
        self._globals: dict[str, Any] = {}
        self._locals: dict[str, Any] = {}
        self._stack: list[dict[str, Any]] = []

    def extend(self, extensions: dict[str, Any]) -> None:
        """Add locals until the current scope is popped."""
        self._locals.update(extensions)

    def extend_globals(self, extensions: dict[str, Any]) -> None:
        """Add names for the rest of the launch (locals of the same name still win)."""
        self._globals.update(extensions)

    def push(self) -> None:
        self._stack.append(dict(self._locals))

    def pop(self) -> None:
        self._locals = pop_saved(self._stack, 'a pop of the launch locals', 'push')

    def as_dict(self) -> dict[str, Any]:
        return {**self._globals, **self._locals}

    def view(self) -> LocalsView:
        return LocalsView(self.as_dict())

    def copy(self) -> 'LaunchLocals':
        copied = LaunchLocals()
        copied._globals, copied._locals = dict(self._globals), dict(self._locals)
        copied._stack = [dict(scope) for scope in self._stack]
        return copied
