"""launch.utilities.type_utils: launch's typed values, the one set of coercion rules for zros.

A launch attribute that is typed (`respawn`, `respawn_delay`, a parameter's `value_type`) may be
written as a value or as substitutions that produce one. The allowed types are the four scalars
`int`, `float`, `bool`, `str` and the uniform lists `List[int]` ... `List[str]`. Text is coerced:
- with no type, by YAML's (1.1) rules: '1' -> 1, '.3' -> 0.3, 'on' -> True, '[1, 2]' -> [1, 2],
  and the result must still be an allowed (uniform) value;
- to `str`, as written; to `int` / `float`, by Python's constructors ('1.' is a float, not an
  int); to `bool`, by YAML plus '1' / '0';
- `can_be_str=True` keeps text that does not coerce (launch's frontends embed substitutions in
  strings, so a list may mix strings with values of the type).

`normalize_typed_substitution` prepares such a value when an action is built and
`perform_typed_substitution` evaluates it when the action runs. zros.launch.template's `Typed`
converts its text through `coerce_to_type`, so `zros launch` follows these rules too.
"""
from __future__ import annotations

import typing
from collections.abc import Iterable
from typing import Any, List

import yaml

from zros.launch.template import Substitution
from zros.launch.utilities.ensure_argument_type_impl import ensure_argument_type
from zros.launch.utilities.normalize_to_list_of_substitutions_impl import normalize_to_list_of_substitutions
from zros.launch.utilities.perform_substitutions_impl import perform_substitutions

__all__ = [
    'ScalarTypesTuple', 'ListTypesTuple', 'AllowedTypesTuple', 'is_typing_list', 'is_valid_scalar_type',
    'extract_type', 'is_instance_of_valid_type', 'is_instance_of', 'coerce_to_type', 'coerce_list',
    'get_typed_value', 'is_substitution', 'normalize_typed_substitution', 'is_normalized_substitution',
    'perform_typed_substitution',
]

#: The scalar types a typed launch value may have.
ScalarTypesTuple = (int, float, bool, str)
#: The uniform list types a typed launch value may have.
ListTypesTuple = (List[int], List[float], List[bool], List[str])
AllowedTypesTuple = ScalarTypesTuple + ListTypesTuple


def is_typing_list(data_type: Any) -> bool:
    """Whether `data_type` is `typing.List` or `List[X]` (the builtin `list` is not)."""
    if data_type is List:
        return True
    return typing.get_origin(data_type) is list and data_type is not list and bool(typing.get_args(data_type))


def is_valid_scalar_type(data_type: Any) -> bool:
    """Whether `data_type` is one of int, float, bool, str."""
    return data_type in ScalarTypesTuple


def extract_type(data_type: Any) -> tuple[type, bool]:
    """`(scalar type, is_list)`: `List[int]` -> `(int, True)`, `bool` -> `(bool, False)`.

    Raises:
        ValueError: not an allowed type (bare `List` included: its items have no type).
    """
    scalar, is_list = data_type, False
    if is_typing_list(data_type) and typing.get_args(data_type):
        scalar, is_list = typing.get_args(data_type)[0], True
    if not is_valid_scalar_type(scalar):
        raise ValueError(f'unsupported data type {data_type!r}: expected int, float, bool, str '
                         'or List[int], List[float], List[bool], List[str]')
    return scalar, is_list


def is_instance_of_valid_type(value: Any, *, can_be_str: bool = False) -> bool:
    """Whether `value` is an allowed scalar, or a uniform list of one scalar type (empty
    included); with `can_be_str`, a list may also hold strings beside its one other type."""
    if not isinstance(value, list):
        return isinstance(value, ScalarTypesTuple)
    member = next((type(item) for item in value if type(item) is not str), str)
    if member not in ScalarTypesTuple:
        return False
    accepted: tuple[type, ...] = (member, str) if can_be_str else (member,)
    return all(isinstance(item, accepted) for item in value)


def is_instance_of(value: Any, data_type: Any = None, *, can_be_str: bool = False) -> bool:
    """Whether `value` is a `data_type` (None: any allowed type); `can_be_str` also accepts
    strings, for a scalar or for a list's items.

    Raises:
        ValueError: `data_type` is not an allowed type.
    """
    if data_type is None:
        return is_instance_of_valid_type(value, can_be_str=can_be_str)
    scalar, is_list = extract_type(data_type)
    accepted: tuple[type, ...] = (str, scalar) if can_be_str else (scalar,)
    if not is_list:
        return isinstance(value, accepted)
    return isinstance(value, list) and all(isinstance(item, accepted) for item in value)


def _from_yaml(text: str, what: str, can_be_str: bool) -> Any:
    """`text` typed by YAML; '' stays ''. Fails unless the result is an allowed value."""
    if not text:
        return text
    try:
        value = yaml.safe_load(text)
    except yaml.YAMLError as exc:
        if can_be_str:
            return text
        raise ValueError(f'{what}: it is not valid YAML ({exc})') from None
    if not is_instance_of_valid_type(value, can_be_str=can_be_str):
        raise ValueError(f'{what}: YAML gives a {type(value).__name__}, not an allowed value')
    return value


def coerce_to_type(value: str, data_type: Any = None, *, can_be_str: bool = False) -> Any:
    """`value` (text) as a `data_type` (None: whatever YAML makes of it), by the module's rules.

    Raises:
        TypeError: `value` is not a string.
        ValueError: it does not coerce, or `data_type` is not an allowed type.
    """
    ensure_argument_type(value, str, 'value', 'coerce_to_type')
    if data_type is None:
        return _from_yaml(value, f'cannot type {value!r} by YAML rules', can_be_str)
    scalar, is_list = extract_type(data_type)
    accepted: tuple[type, ...] = (str, scalar) if can_be_str else (scalar,)
    what = f'cannot convert {value!r} to {_type_name(data_type)}'
    if is_list:
        result = _from_yaml(value, what, can_be_str)
        if not isinstance(result, list) or not all(isinstance(item, accepted) for item in result):
            raise ValueError(f'{what}: got {result!r}')
        return result
    if scalar is str:
        return value
    if scalar in (int, float):
        try:
            return scalar(value)
        except ValueError:
            if can_be_str:
                return value
            raise ValueError(what) from None
    # bool: YAML's spellings (true, on, yes, ...) and, as for conditions, '1' and '0'
    result = _from_yaml({'1': 'true', '0': 'false'}.get(value, value), what, can_be_str)
    if isinstance(result, accepted):
        return result
    raise ValueError(what)


def coerce_list(value: list[str], data_type: type | None = None, *, can_be_str: bool = False) -> list:
    """Each string of `value` coerced to the scalar `data_type` (None: by YAML); the result must
    be a uniform list.

    Raises:
        TypeError: `value` is not a list of strings.
        ValueError: an item does not coerce, or the items end up of different types.
    """
    ensure_argument_type(value, list, 'value', 'coerce_list')
    result = [coerce_to_type(item, data_type, can_be_str=can_be_str) for item in value]
    if not is_instance_of_valid_type(result, can_be_str=can_be_str):
        raise ValueError(f'cannot convert {value!r} to a uniform list: got {result!r}')
    return result


def get_typed_value(value: str | list[str], data_type: Any, *, can_be_str: bool = False) -> Any:
    """`coerce_to_type` for a string, `coerce_list` for a list of strings (then `data_type`
    must be a `List[X]` or None).

    Raises:
        TypeError: a list for a scalar type, or `value` is neither text nor a list of it.
        ValueError: the coercion failed.
    """
    if not isinstance(value, list):
        return coerce_to_type(value, data_type, can_be_str=can_be_str)
    return coerce_list(value, _list_item_type_for(value, data_type, TypeError), can_be_str=can_be_str)


def _list_item_type_for(value: list, data_type: Any, error: type[Exception]) -> type | None:
    """The item type `data_type` asks of the list `value` (None: any allowed type).

    Raises:
        error: `data_type` is a scalar type (launch raises TypeError or ValueError by caller).
        ValueError: `data_type` is not an allowed type.
    """
    if data_type is None:
        return None
    scalar, is_list = extract_type(data_type)
    if not is_list:
        raise error(f'{value!r} is a list, but {_type_name(data_type)} is a scalar type')
    return scalar


def is_substitution(value: Any) -> bool:
    """Whether `value` is a Substitution, or a non-empty sequence of strings and Substitutions
    holding at least one Substitution (plain strings alone are text, not a substitution)."""
    if isinstance(value, Substitution):
        return True
    if isinstance(value, str) or not isinstance(value, Iterable):
        return False
    items = list(value)
    return (bool(items) and all(isinstance(item, (Substitution, str)) for item in items)
            and any(isinstance(item, Substitution) for item in items))


def is_normalized_substitution(value: Any) -> bool:
    """Whether `value` is a non-empty list of Substitution objects only."""
    return isinstance(value, list) and bool(value) and all(isinstance(item, Substitution) for item in value)


# The list type that plain items of these types form, tried in order (ints alone stay ints).
_UNIFORM_LISTS = ((str, frozenset({str})), (bool, frozenset({bool})), (int, frozenset({int})),
                  (float, frozenset({int, float})))


def normalize_typed_substitution(value: Any, data_type: Any) -> Any:
    """Prepare `value` (a value of `data_type`, substitutions, or a list mixing values and
    substitutions) for `perform_typed_substitution`.

    A scalar is checked and kept; a substitution (or a list of strings and substitutions, which
    is one concatenated substitution) becomes a normalized list of substitutions; any other list
    is a list value whose substitution items are each normalized (write `['a', [sub]]` for a
    list of two strings). Plain strings in a list stay strings and ints in a float list become
    floats.

    Raises:
        TypeError: the value can never be a `data_type` (e.g. a list for a scalar type).
        ValueError: `data_type` is not an allowed type.
    """
    if isinstance(value, ScalarTypesTuple):
        if not is_instance_of(value, data_type):
            raise TypeError(f'{value!r} is not a {_type_name(data_type)}')
        return value
    if is_substitution(value):
        return normalize_to_list_of_substitutions(value)
    if not isinstance(value, Iterable):
        raise TypeError(f'expected a value, a substitution or a list of values and substitutions, '
                        f'got {type(value).__name__}')
    items = list(value)
    seen: set[type] = set()
    for item in items:
        if isinstance(item, ScalarTypesTuple):
            seen.add(type(item))
        elif not is_substitution(item):
            raise TypeError(f'a list item must be a value, a substitution or a list of substitutions, got {item!r}')
    scalar = _list_item_type_for(items, data_type, TypeError)
    item_type = _list_item_type(seen, items)
    if scalar is not None and item_type is not None and scalar is not item_type:
        raise TypeError(f'{items!r} is a list of {item_type.__name__}, expected a list of {scalar.__name__}')
    return [normalize_to_list_of_substitutions(item) if is_substitution(item)
            else float(item) if item_type is float else item for item in items]


def _list_item_type(seen: set[type], items: list) -> type | None:
    """The item type of a list whose plain items have the types `seen` (None: substitutions
    only, so any type).

    Raises:
        TypeError: the plain items do not form a uniform list.
    """
    if not seen:
        return None
    for kind, members in _UNIFORM_LISTS:
        if seen <= members:
            return kind
    raise TypeError(f'the list {items!r} mixes values of different types')


def perform_typed_substitution(context: Any, value: Any, data_type: Any) -> Any:
    """Evaluate what `normalize_typed_substitution` returned and coerce it to `data_type`
    (None: by YAML rules, to any allowed value).

    Raises:
        TypeError: a plain value that is not a `data_type`, or `value` is not normalized.
        ValueError: the result does not coerce, a list was given for a scalar type, or
            `data_type` is not an allowed type.
    """
    if isinstance(value, ScalarTypesTuple):
        if data_type is not None and not is_instance_of(value, data_type):
            raise TypeError(f'{value!r} is not a {_type_name(data_type)}')
        return value
    if is_normalized_substitution(value):
        return coerce_to_type(perform_substitutions(context, value), data_type)
    if not isinstance(value, list):
        raise TypeError(f'{value!r} is not a normalized typed substitution')
    scalar = _list_item_type_for(value, data_type, ValueError)
    result = [coerce_to_type(perform_substitutions(context, item), scalar)
              if is_normalized_substitution(item) else item for item in value]
    if not is_instance_of(result, data_type):
        raise ValueError(f'the list {result!r} is not a uniform list'
                         + (f' of {scalar.__name__}' if scalar is not None else ''))
    return result


def _type_name(data_type: Any) -> str:
    return data_type.__name__ if isinstance(data_type, type) else str(data_type)
