"""`LaunchDescriptionEntity`: what a launch description is made of (launch's base class).

Actions and launch descriptions are both entities: resolution visits one, and what `visit`
returns is visited next. The `describe*` methods let tools walk a description without resolving
it (`--show-args`, introspection) and user code check what it built.
"""
from __future__ import annotations

from collections.abc import Iterable
from typing import Any

__all__ = ['LaunchDescriptionEntity', 'SomeEntitiesType_types_tuple']


class LaunchDescriptionEntity:
    """Base of `Action` and `LaunchDescription`; a user's subclass overrides `visit`."""

    #: only actions take a condition; resolution and `--show-args` read it on every entity
    condition: Any = None

    def describe(self) -> str:
        """One line naming the entity; every concrete entity says what it is."""
        raise NotImplementedError(f'{type(self).__name__} must define describe()')

    def describe_sub_entities(self) -> list[Any]:
        """The entities this one always returns, known without resolving anything."""
        return []

    def sub_actions(self) -> list[Any]:
        """zros's name for `describe_sub_entities` (what `--show-args` walks)."""
        return self.describe_sub_entities()

    def describe_conditional_sub_entities(self) -> list[tuple[str, list[Any]]]:
        """Entities returned only in some cases, as `(when, entities)` pairs (none here: zros
        actions with such children, like event handlers, list them as sub-entities)."""
        return []

    def visit(self, context: Any) -> list[Any] | None:
        """Carry the entity out in `context`; returns the entities to visit next."""
        return None

    def get_asyncio_future(self) -> Any:
        """launch's hook for entities that keep running after `visit`; zros's resolution
        finishes every entity in `visit`, so there is never one."""
        return None


#: What a handler may return: one entity or an iterable of them (launch's isinstance tuple).
SomeEntitiesType_types_tuple = (LaunchDescriptionEntity, Iterable)
