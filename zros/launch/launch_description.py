"""`LaunchDescription`: what a Python launch file's `generate_launch_description()` returns.

It is a list of actions; resolving it visits them in order (it is itself an entity, so a
description may sit inside another one's list, as in launch).
"""
from __future__ import annotations

from typing import Any, Iterable

from zros.launch.errors import LaunchFileError
from zros.launch.launch_description_entity import LaunchDescriptionEntity
from zros.launch.origin import origin_here

__all__ = ['LaunchDescription']


class LaunchDescription(LaunchDescriptionEntity):
    """`LaunchDescription([actions...])`, with `add_action` / `add_entity` as in launch."""

    condition = None

    def __init__(self, initial_entities: Iterable[Any] | None = None, *,
                 deprecated_reason: str | None = None) -> None:
        self.origin = origin_here('LaunchDescription')
        self.deprecated_reason = deprecated_reason
        self._entities: list = []
        for entity in initial_entities or []:
            self.add_entity(entity)

    @property
    def entities(self) -> list:
        return list(self._entities)

    @property
    def deprecated(self) -> bool:
        """Whether the file that returns this description says it is deprecated."""
        return self.deprecated_reason is not None

    def add_entity(self, entity: Any) -> None:
        if not isinstance(entity, LaunchDescriptionEntity):
            raise LaunchFileError(origin_here('LaunchDescription'),
                                  f'expected a launch action, got {type(entity).__name__} {entity!r:.60}')
        self._entities.append(entity)

    add_action = add_entity

    def describe_sub_entities(self) -> list:
        return self.entities

    def sub_actions(self) -> list:
        return self.entities

    def get_launch_arguments(self) -> list:
        """The DeclareLaunchArgument actions, found without resolving anything; each notes in
        `_conditionally_included` whether a condition stands above it (launch's flag)."""
        from zros.launch.actions.arg import DeclareLaunchArgument
        found: list = []
        stack = [(entity, False) for entity in reversed(self._entities)]
        while stack:
            entity, conditional = stack.pop()
            conditional = conditional or entity.condition is not None
            if isinstance(entity, DeclareLaunchArgument):
                entity._conditionally_included = conditional
                found.append(entity)
            children = [(child, conditional) for child in entity.describe_sub_entities()]
            children += [(child, True) for _, entities in entity.describe_conditional_sub_entities()
                         for child in entities]
            stack.extend(reversed(children))
        return found

    def visit(self, context: Any) -> list:
        return self.entities

    def __repr__(self) -> str:
        return f'<LaunchDescription of {len(self._entities)} entities>'

    def describe(self) -> str:
        return repr(self)
