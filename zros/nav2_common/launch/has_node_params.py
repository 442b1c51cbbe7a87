"""HasNodeParams: whether a parameter file holds a section for a node (Nav2's bringup starts
the docking server or the route server only when the file configures them)."""
from __future__ import annotations

from typing import Any

import yaml

from zros.launch.template import Substitution, perform, to_template
from zros.nav2_common.launch._files import read_source

__all__ = ['HasNodeParams']


class HasNodeParams(Substitution):
    """`HasNodeParams(source_file, node_name)`: performs to 'True' when `source_file` has
    `node_name: {ros__parameters: ...}` at its top level, else 'False'.

    :param source_file: the parameter file (substitutions allowed).
    :param node_name: the node's name (substitutions allowed).
    """

    def __init__(self, source_file: Any, node_name: Any) -> None:
        self._source = to_template(source_file)
        self._node = to_template(node_name)

    def describe(self) -> str:
        return 'HasNodeParams()'

    def perform(self, context: Any) -> str:
        try:
            data = yaml.safe_load(read_source(perform(self._source, context), 'HasNodeParams'))
        except yaml.YAMLError:
            data = None
        section = data.get(perform(self._node, context)) if isinstance(data, dict) else None
        return str(isinstance(section, dict) and 'ros__parameters' in section)
