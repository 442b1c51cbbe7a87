"""Conditions: whether an action runs (launch.conditions).

Every action takes `condition=`; the YAML front end builds the same objects from `if:` and
`unless:`. A condition is evaluated when resolution reaches its action, and an expression that
is not a boolean (`true`/`1`/`false`/`0`) is an error naming where the condition was written.
"""
from __future__ import annotations

import warnings
from typing import Any, Callable

from zros.launch.errors import LaunchFileError, Origin
from zros.launch.files import module_getattr
from zros.launch.origin import origin_here
from zros.launch.template import SubstitutionError, Text, to_bool

__all__ = ['Condition', 'IfCondition', 'UnlessCondition', 'LaunchConfigurationEquals',
           'LaunchConfigurationNotEquals', 'InvalidConditionExpressionError', 'evaluate_condition_expression']

__getattr__ = module_getattr(__name__)


class InvalidConditionExpressionError(LaunchFileError):
    """A condition's expression is not one of true / 1 / false / 0; the message names where the
    condition was written (launch's error of that name, a ValueError here too)."""


def evaluate_condition_expression(context: Any, expression: Any, origin: Origin | None = None) -> bool:
    """A condition expression's truth: the substitutions performed, then 'true'/'1' or
    'false'/'0' (case-insensitive, surrounding spaces ignored), as launch evaluates `if` / `unless`.

    Raises:
        InvalidConditionExpressionError: any other text, the empty one included.
    """
    text = Text.of(expression, origin or origin_here('condition'))
    try:
        return to_bool(text.perform(context))
    except SubstitutionError as exc:
        raise InvalidConditionExpressionError(text.origin, str(exc)) from None


class Condition:
    """Base of conditions; `Condition(predicate=f)` runs `f(context) -> bool` (as in launch)."""

    def __init__(self, *, predicate: Callable[[Any], bool] | None = None, origin: Origin | None = None) -> None:
        self.origin = origin or origin_here(type(self).__name__)
        self._predicate = predicate

    def evaluate(self, context: Any) -> bool:
        """The predicate's answer; False without one (as launch's bare Condition())."""
        return False if self._predicate is None else bool(self._predicate(context))

    def describe(self) -> str:
        return type(self).__name__


class IfCondition(Condition):
    """True when the expression is 'true' or '1' (case-insensitive); `if:` in YAML."""

    def __init__(self, predicate_expression: Any, *, origin: Origin | None = None) -> None:
        super().__init__(origin=origin)
        self.expression = Text.of(predicate_expression, self.origin)

    def evaluate(self, context: Any) -> bool:
        return evaluate_condition_expression(context, self.expression)

    def describe(self) -> str:
        return f'{type(self).__name__}({self.expression})'


class UnlessCondition(IfCondition):
    """True when the expression is 'false' or '0'; `unless:` in YAML."""

    def evaluate(self, context: Any) -> bool:
        return not super().evaluate(context)


class LaunchConfigurationEquals(Condition):
    """True when a launch configuration equals `expected_value` as text (an unset one equals
    only None), as in launch, which deprecates it (a UserWarning) for
    `IfCondition(EqualsSubstitution(LaunchConfiguration(name), value))`."""

    def __init__(self, launch_configuration_name: str, expected_value: Any, *,
                 origin: Origin | None = None) -> None:
        super().__init__(origin=origin)
        warnings.warn(f'{type(self).__name__} is deprecated, as in launch: use '
                      f'IfCondition(EqualsSubstitution(LaunchConfiguration(name), value)) (or '
                      f'NotEqualsSubstitution)', UserWarning, stacklevel=2)
        self.name = launch_configuration_name
        self.expected = None if expected_value is None else Text.of(expected_value, self.origin)

    def evaluate(self, context: Any) -> bool:
        expected = None if self.expected is None else self.expected.perform(context)
        return context.launch_configurations.get(self.name) == expected   # a read, recorded

    def describe(self) -> str:
        return f'{type(self).__name__}({self.name!r}, {self.expected})'


class LaunchConfigurationNotEquals(LaunchConfigurationEquals):
    """The negation of LaunchConfigurationEquals."""

    def evaluate(self, context: Any) -> bool:
        return not super().evaluate(context)
