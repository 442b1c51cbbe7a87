"""ReplaceString: a copy of a text file (a parameter file, an RViz config) with strings replaced.

Nav2 uses it to put a robot's namespace into the RViz config (`<robot_namespace>` ->
`/robot1`) and Jazzy's bringup to fill `KEEPOUT_ZONE_ENABLED`-style placeholders.
"""
from __future__ import annotations

from typing import Any

from zros.launch.template import Substitution, perform, to_template
from zros.nav2_common.launch._files import read_source, write_rewritten

__all__ = ['ReplaceString']


class ReplaceString(Substitution):
    """`ReplaceString(source_file, replacements, condition=None)`: performs to the path of a
    copy of `source_file` with each key of `replacements` replaced by its value, or to
    `source_file` itself when `condition` is given and false.

    :param source_file: the file (substitutions allowed).
    :param replacements: {text: replacement (substitutions allowed)}.
    :param condition: a launch Condition (IfCondition ...) that gates the replacement.
    """

    def __init__(self, source_file: Any, replacements: dict, condition: Any = None) -> None:
        self._source = to_template(source_file)
        self._replacements = {key: to_template(value) for key, value in replacements.items()}
        self._condition = condition

    @property
    def name(self) -> Any:
        return self._source

    def describe(self) -> str:
        return 'ReplaceString()'

    def perform(self, context: Any) -> str:
        source = perform(self._source, context)
        if self._condition is not None and not self._condition.evaluate(context):
            return source
        text = read_source(source, 'ReplaceString')
        for old, new in self._replacements.items():
            text = text.replace(old, perform(new, context))
        return write_rewritten(context, source, text)
