"""RewrittenYaml: a parameter file with values and keys rewritten while the launch resolves.

Nav2's launch files pass the launch arguments into the parameter file this way
(`param_rewrites={'use_sim_time': use_sim_time, 'yaml_filename': map_yaml_file}`), so each
server reads them from its own section. The rules, as Nav2's:
- a rewrite named by a leaf key (`use_sim_time`) replaces that key wherever it is a leaf;
- a rewrite named by a dotted path (`amcl.ros__parameters.laser_model_type`, list indices as
  numbers) replaces the value there, and is added when the path runs through `ros__parameters`
  but is not in the file yet;
- `key_rewrites` renames keys at every level; `root_key`, when not empty, puts the whole file
  under that key (the namespace the nodes run in).
Values are strings unless `convert_types` is set: then 'true'/'false' become booleans and numbers
become numbers, as YAML would have read them.
"""
from __future__ import annotations

from typing import Any

import yaml

from zros.launch.template import Substitution, perform, to_template
from zros.nav2_common.launch._files import read_source, write_rewritten

__all__ = ['RewrittenYaml']


def convert(text: str) -> Any:
    """'true' -> True, '1.5' -> 1.5, '3' -> 3; anything else stays text."""
    lowered = text.lower()
    if lowered in ('true', 'false'):
        return lowered == 'true'
    for number in (int, float):
        try:
            return number(text)
        except ValueError:
            pass
    return text


def _leaves(node: Any, path: tuple = ()) -> list[tuple[tuple, Any]]:
    """(path, leaf value) of every leaf of a YAML tree; list items are numbered."""
    if isinstance(node, dict):
        return [leaf for key, value in node.items() for leaf in _leaves(value, path + (key,))]
    if isinstance(node, list) and any(isinstance(item, (dict, list)) for item in node):
        return [leaf for index, value in enumerate(node) for leaf in _leaves(value, path + (index,))]
    return [(path, node)]


def _set(tree: Any, path: list[str], value: Any) -> None:
    """Set `value` at the dotted `path`, making the dictionaries on the way."""
    node = tree
    for position, key in enumerate(path):
        last = position == len(path) - 1
        if isinstance(node, list):
            index = int(key)
            if last:
                node[index] = value
            else:
                node = node[index]
            continue
        if last:
            node[key] = value
        else:
            if not isinstance(node.get(key), (dict, list)):
                node[key] = {}
            node = node[key]


def _rename_keys(node: Any, renames: dict[str, str]) -> Any:
    if isinstance(node, dict):
        return {renames.get(key, key): _rename_keys(value, renames) for key, value in node.items()}
    if isinstance(node, list):
        return [_rename_keys(item, renames) for item in node]
    return node


def rewrite(data: Any, param_rewrites: dict[str, str], key_rewrites: dict[str, str], root_key: str,
            convert_types: bool) -> Any:
    """The rewritten YAML tree (pure: the substitution's rules, module docstring)."""
    value = convert if convert_types else (lambda text: text)
    data = data if isinstance(data, dict) else {}
    paths = {'.'.join(map(str, path)) for path, _ in _leaves(data)}
    for path, _ in _leaves(data):
        if path and isinstance(path[-1], str) and path[-1] in param_rewrites:
            _set(data, list(map(str, path)), value(param_rewrites[path[-1]]))
    for dotted, text in param_rewrites.items():
        if '.' not in dotted:
            continue
        if dotted in paths or 'ros__parameters' in dotted.split('.'):
            _set(data, dotted.split('.'), value(text))
    if key_rewrites:
        data = _rename_keys(data, key_rewrites)
    return {root_key: data} if root_key else data


class RewrittenYaml(Substitution):
    """`RewrittenYaml(source_file, param_rewrites, root_key=None, key_rewrites=None,
    convert_types=False)`: performs to the path of the rewritten copy of `source_file`.

    :param source_file: the parameter file (substitutions allowed).
    :param param_rewrites: {leaf key or dotted path: new value (substitutions allowed)}.
    :param root_key: a key to put the whole file under (a namespace); nothing when empty.
    :param key_rewrites: {key: new key}, applied at every level.
    :param convert_types: read the new values as YAML scalars instead of strings.
    """

    def __init__(self, source_file: Any, param_rewrites: dict, root_key: Any = None,
                 key_rewrites: dict | None = None, convert_types: bool = False) -> None:
        self._source = to_template(source_file)
        self._params = {key: to_template(value) for key, value in param_rewrites.items()}
        self._keys = {key: to_template(value) for key, value in (key_rewrites or {}).items()}
        self._root_key = None if root_key is None else to_template(root_key)
        self._convert_types = convert_types

    @property
    def name(self) -> Any:
        return self._source

    def describe(self) -> str:
        return 'RewrittenYaml()'

    def perform(self, context: Any) -> str:
        from zros.launch.errors import SubstitutionError
        source = perform(self._source, context)
        try:
            data = yaml.safe_load(read_source(source, 'RewrittenYaml'))
        except yaml.YAMLError as exc:
            raise SubstitutionError(f'RewrittenYaml: {source}: invalid YAML: {str(exc).splitlines()[0]}') from None
        rewritten = rewrite(data, {key: perform(value, context) for key, value in self._params.items()},
                            {key: perform(value, context) for key, value in self._keys.items()},
                            perform(self._root_key, context) if self._root_key is not None else '',
                            self._convert_types)
        return write_rewritten(context, source, yaml.safe_dump(rewritten, sort_keys=False))
