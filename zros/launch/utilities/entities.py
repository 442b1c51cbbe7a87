"""launch.utilities' entity walks: flatten "some entities" into a list, and visit an entity
tree depth-first collecting the asyncio futures its entities wait on (launch's service uses
them to know when a launch is idle).

An entity is anything with launch's LaunchDescriptionEntity protocol: `visit(context)` returning
sub-entities (or None) and `get_asyncio_future()` returning a future (or None).
"""
from __future__ import annotations

import asyncio
from collections.abc import Iterable
from typing import Any

__all__ = ['normalize_to_list_of_entities', 'visit_all_entities_and_collect_futures']


def _is_entity(value: Any) -> bool:
    return callable(getattr(value, 'visit', None))


def normalize_to_list_of_entities(entities: Iterable[Any]) -> list[Any]:
    """`entities` with each nested iterable of entities spliced in (one level deep)."""
    flattened: list[Any] = []
    for entity in entities:
        if _is_entity(entity):
            flattened.append(entity)
        else:
            flattened.extend(entity)
    return flattened


def visit_all_entities_and_collect_futures(entity: Any, context: Any) -> list[tuple[Any, asyncio.Future]]:
    """Visit `entity`, then its sub-entities depth-first, and return `(entity, future)` for each
    visited entity that has a future; an entity's future is taken right after its own visit."""
    sub_entities = entity.visit(context)
    # an entity without get_asyncio_future (a zros Action before it learns one) waits on nothing
    get_future = getattr(entity, 'get_asyncio_future', None)
    future = get_future() if get_future is not None else None
    collected = [(entity, future)] if future is not None else []
    for sub_entity in sub_entities or ():
        collected.extend(visit_all_entities_and_collect_futures(sub_entity, context))
    return collected
