"""launch.substitutions.substitution_failure: launch's module path of `SubstitutionFailure`, which
zros keeps as zros.launch.errors.SubstitutionError (so `except SubstitutionFailure` catches what
every substitution raises, whichever module named it)."""
from __future__ import annotations

from zros.launch.errors import SubstitutionError as SubstitutionFailure

__all__ = ['SubstitutionFailure']
