"""`OpaqueFunction`: Python code that runs while the launch resolves and returns more actions."""
from __future__ import annotations

import traceback
from typing import Any, Callable

from zros.launch.action import Action
from zros.launch.errors import LaunchError, LaunchFileError, Origin

__all__ = ['OpaqueFunction', 'call_user_function']


def call_user_function(function: Callable, origin: Origin, *args: Any, **kwargs: Any) -> Any:
    """Call a launch file's function; anything it raises becomes one located LaunchFileError
    (at the line of the function that raised, or at `origin`)."""
    try:
        return function(*args, **kwargs)
    except LaunchFileError:
        raise
    except LaunchError as exc:   # a substitution performed inside the function, without location
        raise LaunchFileError(origin, str(exc)) from None
    except Exception as exc:  # noqa: BLE001 - the user's code: reported, never a traceback
        code = getattr(function, '__code__', None)
        where = origin
        if code is not None:
            for frame in traceback.extract_tb(exc.__traceback__):
                if frame.filename == code.co_filename:
                    where = Origin(frame.filename, frame.lineno or origin.line, origin.tag)
        message = str(exc).strip().splitlines()[0] if str(exc).strip() else ''
        name = getattr(function, '__name__', 'function')
        raise LaunchFileError(where, f'{name}() raised {type(exc).__name__}' + (f': {message}' if message else '')) \
            from None


class OpaqueFunction(Action):
    """`OpaqueFunction(function=f, args=[...], kwargs={...})`: `f(context, *args, **kwargs)` runs
    when resolution reaches it and may return actions (or None). `context` is the launch
    context: `LaunchConfiguration('x').perform(context)`, `context.launch_configurations`."""

    def __init__(self, *, function: Callable, args: Any = None, kwargs: Any = None, **action_kwargs: Any) -> None:
        super().__init__(**action_kwargs)
        if not callable(function):
            raise LaunchFileError(self.origin.with_key('function'), f'expected a function, got {type(function).__name__}')
        self.function = function
        self.args = list(args or [])
        self.kwargs = dict(kwargs or {})

    def execute(self, context: Any) -> list[Action]:
        from zros.launch.actions.group import check_actions
        result = call_user_function(self.function, self.origin, context, *self.args, **self.kwargs)
        return check_actions(result, self.origin)
