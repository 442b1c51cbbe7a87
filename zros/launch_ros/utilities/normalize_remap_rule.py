"""launch_ros.utilities.normalize_remap_rule: a `remappings=[(from, to)]` rule as two tuples of
substitutions, so both sides may be text, substitutions or lists of them."""
from __future__ import annotations

from collections.abc import Iterable, Iterator
from typing import Any

from zros.launch.template import Substitution
from zros.launch.utilities import ensure_argument_type, normalize_to_list_of_substitutions

__all__ = ['normalize_remap_rule', 'normalize_remap_rules']

RemapRule = tuple[tuple[Substitution, ...], tuple[Substitution, ...]]


def normalize_remap_rule(remap_rule: Any) -> RemapRule:
    """`(from, to)` with each side normalized to a tuple of substitutions.

    Raises:
        TypeError: `remap_rule` is not a tuple of two, or a side is not some substitutions.
    """
    ensure_argument_type(remap_rule, tuple, 'remap_rule', 'normalize_remap_rule')
    if len(remap_rule) != 2:
        raise TypeError(f'a remap rule is a (from, to) tuple, got {len(remap_rule)} items')
    source, target = remap_rule
    return tuple(normalize_to_list_of_substitutions(source)), tuple(normalize_to_list_of_substitutions(target))


def normalize_remap_rules(remap_rules: Iterable[Any]) -> Iterator[RemapRule]:
    """Each rule of `remap_rules` normalized, lazily (as launch_ros yields them)."""
    for rule in remap_rules:
        yield normalize_remap_rule(rule)
