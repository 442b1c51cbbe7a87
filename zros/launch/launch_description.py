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

    def get_launch_arguments(self, conditional_inclusion: bool = False) -> list:
        """The DeclareLaunchArgument actions, found without resolving anything (included files
        too, when their path needs no launch configuration); each notes in
        `_conditionally_included` whether a condition stands above it (launch's flag)."""
        return [argument for argument, _ in
                self.get_launch_arguments_with_include_launch_description_actions(conditional_inclusion)]

    def get_launch_arguments_with_include_launch_description_actions(
            self, conditional_inclusion: bool = False) -> list[tuple[Any, list | None]]:
        """`get_launch_arguments`, each with the IncludeLaunchDescription actions it is below
        (None at this description's top level), as launch's check of an include's required
        arguments wants them. The first declaration of a name wins, and nothing after a
        ResetLaunchConfigurations is looked at (a command-line value cannot reach it)."""
        from zros.launch.actions.arg import DeclareLaunchArgument
        from zros.launch.actions.include import IncludeLaunchDescription
        from zros.launch.actions.arg import ResetLaunchConfigurations
        found: dict[str, tuple[Any, list | None]] = {}

        def visit(entities: list, conditional: bool, includes: list | None) -> None:
            for entity in entities:
                entity_conditional = conditional or entity.condition is not None
                if isinstance(entity, DeclareLaunchArgument) and entity.name not in found:
                    entity._conditionally_included = entity_conditional
                    found[entity.name] = (entity, includes)
                if isinstance(entity, ResetLaunchConfigurations):
                    return
                below = [*(includes or []), entity] if isinstance(entity, IncludeLaunchDescription) else includes
                visit(entity.describe_sub_entities(), entity_conditional, below)
                for _, children in entity.describe_conditional_sub_entities():
                    visit(children, True, below)

        visit(self._entities, conditional_inclusion, None)
        return list(found.values())

    def visit(self, context: Any) -> list:
        return self.entities

    def __repr__(self) -> str:
        return f'<LaunchDescription of {len(self._entities)} entities>'

    def describe(self) -> str:
        return repr(self)
