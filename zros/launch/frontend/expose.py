"""The tag and substitution registries that every front end reads (launch.frontend.expose).

A launch tag is known to the parser because a class or a function was *exposed* under its
name: `@expose_action('node')` on a class with a `parse(entity, parser)` classmethod, or on a
plain function with that signature. zros's own actions are exposed the same way (through
`zros.launch.action.launch_tag`), so a tag added by an extension module is a tag like any
other, for `Parser.parse_description` as for `zros launch`.
"""
from __future__ import annotations

import functools
import inspect
from typing import TYPE_CHECKING, Any, Callable, Iterable

if TYPE_CHECKING:
    from zros.launch.action import Action
    from zros.launch.entity import Entity
    from zros.launch.frontend.parser import Parser

__all__ = ['expose_action', 'expose_substitution', 'instantiate_action', 'instantiate_substitution',
           'action_parse_methods', 'substitution_parse_methods']

#: tag -> `parse(entity, parser) -> (action class, kwargs)`, checking the entity is fully read.
action_parse_methods: dict[str, Callable[..., tuple[Any, dict]]] = {}
#: substitution name -> `parse(args) -> (substitution class, kwargs)`.
substitution_parse_methods: dict[str, Callable[..., tuple[Any, dict]]] = {}


def instantiate_action(entity: Entity, parser: Parser) -> Action:
    """The action an entity describes, built by the parse method exposed for its tag.

    Raises:
        RuntimeError: no action is exposed under the entity's tag.
    """
    parse = action_parse_methods.get(entity.type_name)
    if parse is None:
        raise RuntimeError(f'Unrecognized entity of the type: {entity.type_name}')
    action_type, kwargs = parse(entity, parser)
    return action_type(**kwargs)


def instantiate_substitution(type_name: str, args: Iterable[Any] | None = None) -> Any:
    """The substitution `$(type_name args...)` built by its exposed parse method."""
    parse = substitution_parse_methods.get(type_name)
    if parse is None:
        raise RuntimeError(f'Unknown substitution: {type_name}')
    substitution_type, kwargs = parse([] if args is None else list(args))
    return substitution_type(**kwargs)


def _registered(method: Callable) -> Callable:
    """What a registry entry stands for (an action's entry wraps the exposed parse method)."""
    return getattr(method, '__wrapped__', method)


def __expose_impl(name: str, parse_methods_map: dict, exposed_type: str) -> Callable[[Any], Any]:
    """A decorator storing the parse method of what it decorates in `parse_methods_map[name]`.

    A class contributes its `parse` classmethod, a function itself. An action's entry also
    checks, once parsed, that the entity has no attribute or child nobody read, so a misspelled
    attribute of an extension's tag is an error as it is for a built-in one. Exposing the same
    method twice is harmless (a module imported again); two different ones under one name are not.

    Raises:
        RuntimeError: not a parse function nor a class with a `parse` classmethod, or `name`
            already taken by another method.
    """
    def expose(exposed: Any) -> Any:
        if inspect.isclass(exposed):
            if not inspect.ismethod(getattr(exposed, 'parse', None)):
                raise RuntimeError("Did not find a class method called 'parse' in the class being decorated.")
            method = exposed.parse
        elif inspect.isfunction(exposed):
            method = exposed
        else:
            raise RuntimeError(f'Exposed {exposed_type} parser for {name} is not a callable or a class '
                               'containing a parse method')
        if name in parse_methods_map and _registered(parse_methods_map[name]) != method:
            raise RuntimeError(f'Two {exposed_type} parsing methods exposed with the same name: [{name}].')
        if exposed_type == 'action':
            parse_methods_map[name] = _checked_parse(method)
        else:
            parse_methods_map[name] = method
        return exposed
    return expose


def _checked_parse(method: Callable) -> Callable:
    @functools.wraps(method)
    def parse(entity: Entity, parser: Parser) -> tuple[Any, dict]:
        parsed = method(entity, parser)
        entity.assert_entity_completely_parsed()
        return parsed
    return parse


def expose_action(name: str) -> Callable[[Any], Any]:
    """Class or function decorator: `@expose_action('my_tag')` makes `<my_tag>` a launch tag."""
    return __expose_impl(name, action_parse_methods, 'action')


def expose_substitution(name: str) -> Callable[[Any], Any]:
    """Function decorator: `@expose_substitution('my_subst')` makes `$(my_subst ...)` parse."""
    return __expose_impl(name, substitution_parse_methods, 'substitution')
