"""normalize_parameters / evaluate_parameters: a Node's `parameters=[...]` prepared, then
evaluated, as launch_ros code sees them (launch_ros.utilities re-exports them; they live here,
in the launch, because LoadComposableNodes builds its LoadNode requests with them).

They are a view of zros's own parameter model (zros.launch.parameters), the one `zros launch`
resolves nodes with: `normalize_parameters` builds its `ParamEntry`s, `evaluate_parameters`
performs them and reshapes the result the way launch_ros returns it: a `pathlib.Path` per
parameter file and a `{dotted name: value}` dict per dict given, list values as tuples.
"""
from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from zros.launch.errors import LaunchFileError
from zros.launch.origin import origin_here
from zros.launch.parameters import ParamEntry, param_entries

__all__ = ['normalize_parameters', 'evaluate_parameters']


def normalize_parameters(parameters: Sequence[Any]) -> tuple[Any, ...]:
    """Each item of a `parameters=` list prepared for `evaluate_parameters`: a dict (nested
    dicts give dotted names; keys and values may be substitutions) or a parameter file (a path,
    substitutions, or a ParameterFile).

    Raises:
        TypeError: `parameters` is not a list, or an item is none of those.
    """
    if isinstance(parameters, (str, Mapping)) or not isinstance(parameters, Sequence):
        raise TypeError(f'expected a list of parameter dicts and files, got {type(parameters).__name__}')
    origin = origin_here('parameters')
    normalized: list[Any] = []
    for item in parameters:
        try:
            entries = param_entries([item], origin)
        except LaunchFileError as exc:
            raise TypeError(exc.reason) from None
        # a dict is kept as the group of its entries, so it evaluates to one dict again
        normalized.append(entries if isinstance(item, Mapping) else entries[0])
    return tuple(normalized)


def evaluate_parameters(context: Any, parameters: Sequence[Any]) -> tuple[Any, ...]:
    """What `normalize_parameters` gave, evaluated in `context`: a Path per file, a dict of
    dotted names to values per dict (a list value as a tuple), and a one-entry dict per
    `Parameter(name, value)` (launch_ros returns the description itself).

    Raises:
        TypeError: a value cannot be a ROS parameter (a mixed, nested or empty list).
        LaunchFileError: a substitution failed.
    """
    evaluated: list[Any] = []
    for item in parameters:
        if isinstance(item, ParamEntry) and item.path is not None:
            evaluated.append(Path(item.path.perform(context)))
            continue
        # a dict's entries; a Parameter(name, value) description gives a one-entry dict
        values: dict[str, Any] = {}
        for entry in (item,) if isinstance(item, ParamEntry) else item:
            _flatten(entry, '', context, values)
        evaluated.append(values)
    return tuple(evaluated)


def _flatten(entry: ParamEntry, prefix: str, context: Any, out: dict[str, Any]) -> None:
    assert entry.name is not None, 'a named entry (dict key or Parameter)'
    name = prefix + entry.name.perform(context)
    if entry.value is None:
        for nested in entry.nested:
            _flatten(nested, name + '.', context, out)
        return
    value = entry.value.perform(context)
    # launch_ros turns lists into tuples, except those a ParameterValue(value_type=) typed
    out[name] = tuple(value) if isinstance(value, list) and entry.value.type is None else value

