"""`launch_testing.actions.ReadyToTest`: the point in a test's launch where its tests may start.

Resolved like any launch action, it becomes a call the supervisor makes when the launch reaches
it, after starting the processes before it (zros.launch.plan.CallEffect); the launch test
runner (zros.launch_testing.runner) is what listens.
"""
from __future__ import annotations

from typing import Any, Callable

from zros.launch.action import Action
from zros.launch.files import module_getattr
from zros.launch.plan import CallEffect

__all__ = ['ReadyToTest']


class ReadyToTest(Action):
    """Tells the launch test that it may run its active tests now (as launch_testing's)."""

    def __init__(self, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self._callbacks: list[Callable[[], None]] = []

    def _add_callback(self, callback: Callable[[], None]) -> None:
        """Called by the runner that launches the description (launch_testing's name)."""
        self._callbacks.append(callback)

    def execute(self, context: Any) -> None:
        context.emit(CallEffect('ready to test', self._ready, self.origin))

    def _ready(self) -> None:
        for callback in self._callbacks:
            callback()


__getattr__ = module_getattr(__name__)   # GTest, PyTest: one line saying what there is
