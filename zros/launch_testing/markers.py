"""`launch_testing.markers`: `@keep_alive` (the launch runs until the tests end, even when
every process has exited) and `@retry_on_failure(times=N)` on test methods."""
from __future__ import annotations

import functools
import time
from typing import Any, Callable

__all__ = ['keep_alive', 'retry_on_failure']


def keep_alive(test_description: Callable) -> Callable:
    """Mark generate_test_description: keep the launch up until the tests are done."""
    markers = getattr(test_description, '__markers__', None)
    if markers is None:
        markers = test_description.__markers__ = {}
    markers['keep_alive'] = True
    return test_description


def retry_on_failure(*, times: int, delay: float | None = None) -> Callable[[Callable], Callable]:
    """Run a test method up to `times` times while it fails an assertion (`delay` s apart)."""
    if times < 1:
        raise ValueError('retry_on_failure needs times >= 1')

    def decorate(method: Callable) -> Callable:
        @functools.wraps(method)
        def retried(self: Any, *args: Any, **kwargs: Any) -> Any:
            for _ in range(times - 1):
                try:
                    return method(self, *args, **kwargs)
                except AssertionError:
                    if delay:
                        time.sleep(delay)
            return method(self, *args, **kwargs)
        return retried
    return decorate
