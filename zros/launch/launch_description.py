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

    def add_entity(self, entity: Any) -> None:
        from zros.launch.action import Action
        if not isinstance(entity, (Action, LaunchDescription)):
            raise LaunchFileError(origin_here('LaunchDescription'),
                                  f'expected a launch action, got {type(entity).__name__} {entity!r:.60}')
        self._entities.append(entity)

    add_action = add_entity

    def describe_sub_entities(self) -> list:
        return self.entities

    def sub_actions(self) -> list:
        return self.entities

    def get_launch_arguments(self) -> list:
        """The DeclareLaunchArgument actions, found without resolving anything."""
        from zros.launch.actions.arg import DeclareLaunchArgument
        found, stack = [], list(reversed(self._entities))
        while stack:
            entity = stack.pop()
            if isinstance(entity, DeclareLaunchArgument):
                found.append(entity)
            stack.extend(reversed(entity.sub_actions()))
        return found

    def visit(self, context: Any) -> list:
        return self.entities

    def __repr__(self) -> str:
        return f'<LaunchDescription of {len(self._entities)} entities>'
