"""Conditions: whether an action runs (launch.conditions).

Every action takes `condition=`; the YAML front end builds the same objects from `if:` and
`unless:`. A condition is evaluated when resolution reaches its action, and an expression that
is not a boolean (`true`/`1`/`false`/`0`) is an error naming where the condition was written.
"""
from __future__ import annotations

from typing import Any, Callable

from zros.launch.errors import LaunchFileError, Origin
from zros.launch.files import module_getattr
from zros.launch.origin import origin_here
from zros.launch.template import SubstitutionError, Text, to_bool

__all__ = ['Condition', 'IfCondition', 'UnlessCondition', 'LaunchConfigurationEquals',
           'LaunchConfigurationNotEquals']

__getattr__ = module_getattr(__name__)


class Condition:
    """Base of conditions; `Condition(predicate=f)` runs `f(context) -> bool` (as in launch)."""

    def __init__(self, *, predicate: Callable[[Any], bool] | None = None, origin: Origin | None = None) -> None:
        self.origin = origin or origin_here(type(self).__name__)
        self._predicate = predicate

    def evaluate(self, context: Any) -> bool:
        if self._predicate is None:
            raise NotImplementedError(f'{type(self).__name__} must define evaluate(context)')
        return bool(self._predicate(context))

    def describe(self) -> str:
        return type(self).__name__


class IfCondition(Condition):
    """True when the expression is 'true' or '1' (case-insensitive); `if:` in YAML."""

    def __init__(self, predicate_expression: Any, *, origin: Origin | None = None) -> None:
        super().__init__(origin=origin)
        self.expression = Text.of(predicate_expression, self.origin)

    def evaluate(self, context: Any) -> bool:
        text = self.expression.perform(context)
        try:
            return to_bool(text)
        except SubstitutionError as exc:
            raise LaunchFileError(self.expression.origin, str(exc)) from None

    def describe(self) -> str:
        return f'{type(self).__name__}({self.expression})'


class UnlessCondition(IfCondition):
    """True when the expression is 'false' or '0'; `unless:` in YAML."""

    def evaluate(self, context: Any) -> bool:
        return not super().evaluate(context)


class LaunchConfigurationEquals(Condition):
    """True when a launch configuration equals `expected_value` as text (an unset one equals
    only None), as in launch."""

    def __init__(self, launch_configuration_name: str, expected_value: Any, *,
                 origin: Origin | None = None) -> None:
        super().__init__(origin=origin)
        self.name = launch_configuration_name
        self.expected = None if expected_value is None else Text.of(expected_value, self.origin)

    def evaluate(self, context: Any) -> bool:
        context.note_configuration_read(self.name)
        expected = None if self.expected is None else self.expected.perform(context)
        return context.configurations.get(self.name) == expected

    def describe(self) -> str:
        return f'{type(self).__name__}({self.name!r}, {self.expected})'


class LaunchConfigurationNotEquals(LaunchConfigurationEquals):
    """The negation of LaunchConfigurationEquals."""

    def evaluate(self, context: Any) -> bool:
        return not super().evaluate(context)
