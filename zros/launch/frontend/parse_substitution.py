"""Launch-file text as launch's lists of substitutions (launch.frontend.parse_substitution).

zros parses `$(...)` once, into a template (zros.launch.template); these functions show a
template the way launch's front-end API does: a list of `Substitution` objects, literal text as
`TextSubstitution`. An action's `parse` method gets them through `parser.parse_substitution`.
"""
from __future__ import annotations

import re
from typing import Any

from zros.launch.errors import LaunchFileError, SubstitutionError
from zros.launch.substitutions import TextSubstitution, substitutions_of
from zros.launch.template import Substitution, parse

__all__ = ['parse_substitution', 'parse_if_substitutions', 'replace_escaped_characters']


def parse_substitution(string_value: str) -> list[Substitution]:
    """`'a_$(env X)'` -> `[TextSubstitution('a_'), EnvironmentVariable('X')]`; '' is one empty text.

    Raises:
        LaunchFileError: bad syntax or an unknown substitution (also a ValueError).
    """
    try:
        template = parse(string_value)
    except SubstitutionError as exc:
        raise LaunchFileError(None, str(exc)) from None
    return substitutions_of(template) or [TextSubstitution(text='')]


def parse_if_substitutions(value: Any) -> Any:
    """A string with substitutions as a list of them; a plain string, a number or a bool as it
    is; a list item by item, whose items must then all be of one kind.

    Raises:
        ValueError: a list mixing kinds (`['$(var a)', 1, 1.0]`).
    """
    kinds: set[type] = set()

    def parse_one(item: Any) -> Any:
        if not isinstance(item, str):
            kinds.add(type(item))
            return item
        parsed = parse_substitution(item)
        if len(parsed) == 1 and isinstance(parsed[0], TextSubstitution):
            kinds.add(str)
            return parsed[0].text
        return parsed

    parsed = [parse_one(item) for item in value] if isinstance(value, list) else parse_one(value)
    if len(kinds) > 1:
        raise ValueError('The result is a non-uniform list')
    return parsed


def replace_escaped_characters(data: str) -> str:
    """`\\$` -> `$`: a backslash escapes the character after it, as in launch files' text."""
    return re.sub(r'\\(.)', r'\1', data)
