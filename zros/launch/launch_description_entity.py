"""`LaunchDescriptionEntity` (launch's): what a launch description may hold, the common base of
actions and launch descriptions, so an event handler's result can be checked as launch does."""
from __future__ import annotations

from collections.abc import Iterable

__all__ = ['LaunchDescriptionEntity', 'SomeEntitiesType_types_tuple']


class LaunchDescriptionEntity:
    """An action or a launch description; `visit(context)` returns the entities to visit next."""

    def visit(self, context: object) -> list:
        return []

    def describe_sub_entities(self) -> list:
        return []


#: What a handler may return: one entity or an iterable of them (launch's isinstance tuple).
SomeEntitiesType_types_tuple = (LaunchDescriptionEntity, Iterable)
