"""launch.utilities.perform_substitutions: evaluate a list of substitutions into one string."""
from __future__ import annotations

from collections.abc import Iterable
from typing import Any

__all__ = ['perform_substitutions']


def perform_substitutions(context: Any, subs: Iterable[Any]) -> str:
    """Concatenate what `context.perform_substitution` gives for each item of `subs`.

    Args:
        context: a LaunchContext, or anything with `perform_substitution(sub)`.
        subs: Substitution objects (normalize strings first with
            `normalize_to_list_of_substitutions`).

    Raises:
        TypeError: `subs` is not iterable.
        AttributeError: an item is not a substitution (it has no `perform`), as in launch.
    """
    out = []
    for sub in subs:
        if not hasattr(sub, 'perform'):
            raise AttributeError(f'{sub!r} of type {type(sub).__name__} is not a substitution: '
                                 'it has no perform(context)')
        out.append(context.perform_substitution(sub))
    return ''.join(out)
