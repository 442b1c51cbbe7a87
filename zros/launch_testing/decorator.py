"""Decorators of a launch test module: `@post_shutdown_test()` on test classes that run after
the launch has ended, and `@ready_to_test_action_timeout(s)` on generate_test_description."""
from __future__ import annotations

from typing import Any, Callable

__all__ = ['post_shutdown_test', 'ready_to_test_action_timeout', 'DEFAULT_READY_TIMEOUT']

#: How long the launch may take to reach ReadyToTest [s] (launch_testing's default).
DEFAULT_READY_TIMEOUT = 15.0


def post_shutdown_test() -> Callable[[type], type]:
    """Mark a unittest.TestCase class to run after the launch has shut down."""
    def decorate(test_class: Any) -> Any:
        if not isinstance(test_class, type):
            raise TypeError('post_shutdown_test decorates test classes')
        test_class.__post_shutdown_test__ = True
        return test_class
    return decorate


def ready_to_test_action_timeout(timeout: float) -> Callable[[Callable], Callable]:
    """How long (s) the launch may take to reach ReadyToTest before the test fails."""
    def decorate(function: Callable) -> Callable:
        function.__ready_to_test_action_timeout__ = timeout
        return function
    return decorate
