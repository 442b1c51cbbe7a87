"""Attribute types as the front ends name them (launch.frontend.type_utils).

A `param` or `arg` may say its type in text (`type="list_of_int"`); these map such names, and
launch's `typing.List[...]` spellings, onto the data types `Entity.get_attr` takes.
"""
from __future__ import annotations

import typing
from typing import Any

from zros.launch.entity import Entity

__all__ = ['check_is_list_entity', 'get_data_type_from_identifier']

#: type identifier -> data type; `yaml` (None) means "typed by YAML rules".
_IDENTIFIED_TYPES: dict[str, Any] = {
    'str': str, 'bool': bool, 'float': float, 'int': int,
    'list_of_str': list[str], 'list_of_bool': list[bool], 'list_of_float': list[float], 'list_of_int': list[int],
    'yaml': None,
}


def check_is_list_entity(data_type: Any) -> bool:
    """Whether `data_type` asks for child entities (`List[Entity]` or a list of a subclass)."""
    if typing.get_origin(data_type) is not list:
        return False
    (item,) = typing.get_args(data_type) or (None,)
    return isinstance(item, type) and issubclass(item, Entity)


def get_data_type_from_identifier(type_identifier: str) -> Any:
    """The data type a type identifier names.

    Raises:
        ValueError: not one of str, bool, float, int, list_of_{str,bool,float,int}, yaml.
    """
    if type_identifier not in _IDENTIFIED_TYPES:
        raise ValueError(f"Got invalid type identifier '{type_identifier}'")
    return _IDENTIFIED_TYPES[type_identifier]
