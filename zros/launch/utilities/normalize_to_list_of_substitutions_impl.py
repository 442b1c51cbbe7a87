"""launch.utilities.normalize_to_list_of_substitutions: "some substitutions" (a string, a
Substitution, or an iterable of those) as the list of Substitution objects launch code walks."""
from __future__ import annotations

from typing import Any

from zros.launch.template import Substitution

__all__ = ['normalize_to_list_of_substitutions']


def normalize_to_list_of_substitutions(subs: Any) -> list[Substitution]:
    """A string becomes one TextSubstitution, a Substitution a list of itself, and each item of
    an iterable one of those (strings are kept apart, not joined).

    Unlike zros's own `to_template`, numbers and nested lists are refused, as launch refuses them.

    Raises:
        TypeError: `subs`, or one of its items, is neither a string nor a Substitution.
    """
    if isinstance(subs, (str, Substitution)):
        return [_one(subs)]
    try:
        items = iter(subs)
    except TypeError:
        raise TypeError(f'expected a string, a Substitution or an iterable of them, '
                        f'got {type(subs).__name__}') from None
    return [_one(item) for item in items]


def _one(item: Any) -> Substitution:
    from zros.launch.substitutions import TextSubstitution
    if isinstance(item, Substitution):
        return item
    if isinstance(item, str):
        return TextSubstitution(text=item)
    raise TypeError(f'cannot normalize an item of type {type(item).__name__}: '
                    'expected a string or a launch Substitution')
