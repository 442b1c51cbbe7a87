"""The one parser of markup launch files (launch.frontend.parser).

XML and YAML launch files differ only in how an entity is read (zros.launch.xml_entity,
zros.launch.entity); turning entities into actions is this class's job and is shared. Its
formats (`load_parser_implementations`) are zros's two built-in ones plus any a package
declares under the `launch.frontend.parser` entry point group, and its tags are those exposed
with `expose_action` (zros's own, and those of the modules declared under
`launch.frontend.launch_extension`, loaded before the first tag is parsed). `zros launch`
reads XML and YAML files through this class, so an extension's tag works there too.
"""
from __future__ import annotations

import importlib
import importlib.metadata as importlib_metadata
import io
import os
import traceback
import warnings
from typing import TYPE_CHECKING, Any, ClassVar, TextIO

from zros.launch.entity import Entity
from zros.launch.errors import LaunchFileError
from zros.launch.files import read_text
from zros.launch.frontend.expose import action_parse_methods
from zros.launch.frontend.parse_substitution import (parse_if_substitutions, parse_substitution,
                                                    replace_escaped_characters)
from zros.launch.template import Substitution, Text, Typed

if TYPE_CHECKING:
    from zros.launch.action import Action
    from zros.launch.launch_description import LaunchDescription

__all__ = ['Parser', 'InvalidFrontendLaunchFileError', 'importlib_metadata', 'read_file']


class InvalidFrontendLaunchFileError(LaunchFileError):
    """No front end could read a markup launch file; the message lists what each one said."""

    def __init__(self, extension: str = '', *, likely_errors: list[Exception] | None = None) -> None:
        kind = f"'{extension}' " if extension else ''
        reasons = '; '.join(str(error) for error in likely_errors or []) or 'no front end to read it'
        super().__init__(None, f'invalid {kind}launch file: {reasons}')
        self.likely_errors = likely_errors or []


def _entry_points(group: str) -> list[Any]:
    """The entry points of `group`, from either shape `entry_points()` has had."""
    found = importlib_metadata.entry_points()
    if hasattr(found, 'select'):
        return list(found.select(group=group))
    return list(found.get(group, []))


def read_file(file: str | os.PathLike | TextIO) -> tuple[str, str]:
    """The name and text of a launch file given as a path or as an open text file ('<string>'
    for one without a name, such as an `io.StringIO`)."""
    if isinstance(file, (str, bytes, os.PathLike)):
        path = os.fsdecode(file)
        return path, read_text(path)
    return getattr(file, 'name', '') or '<string>', file.read()


class Parser:
    """Turns the entities of a markup launch file into actions.

    A format subclasses it and overrides `load` (read a file into its root entity) and
    `get_file_extensions`; `parse_description`, `parse_action` and the typed helpers that
    actions' `parse` methods call are shared and not meant to be overridden.

    Args:
        path: the file being parsed, for error messages ('' when unknown).
    """

    extensions_loaded: ClassVar[bool] = False
    frontend_parsers: ClassVar[dict[str, type['Parser']] | None] = None

    def __init__(self, path: str = '') -> None:
        self.path = path

    # -- extensions -------------------------------------------------------------------------------
    @classmethod
    def load_launch_extensions(cls) -> None:
        """Import zros's actions and every module declared under `launch.frontend.launch_extension`
        (once), so their `expose_action` tags are known; a module that fails is a warning."""
        if Parser.extensions_loaded:
            return
        importlib.import_module('zros.launch.actions')
        extensions = _entry_points('launch.frontend.launch_extension')
        if extensions:
            from zros.import_hook import install
            install()   # an extension is written against `launch`, which is zros.launch
        for entry_point in extensions:
            try:
                entry_point.load()
            except Exception:   # a broken extension must not stop the launch files that do not use it
                warnings.warn(f'Failed to load the launch extension: {entry_point.name}\n'
                              f'{traceback.format_exc()}', stacklevel=2)
        Parser.extensions_loaded = True

    @classmethod
    def load_parser_implementations(cls) -> None:
        """The formats: XML and YAML, plus those declared under `launch.frontend.parser` (a
        module that fails is a warning; a declared name does not replace a built-in one)."""
        if Parser.frontend_parsers is not None:
            return
        from zros.launch.frontend.formats import BUILTIN_PARSERS
        parsers = dict(BUILTIN_PARSERS)
        for entry_point in _entry_points('launch.frontend.parser'):
            if entry_point.name in parsers:
                continue
            try:
                parsers[entry_point.name] = entry_point.load()
            except Exception:   # as for extensions: only the files in that format are affected
                warnings.warn(f'Failed to load the parser extension: {entry_point.name}\n'
                              f'{traceback.format_exc()}', stacklevel=2)
        Parser.frontend_parsers = dict(sorted(parsers.items()))

    @classmethod
    def get_available_extensions(cls) -> list[str]:
        """The names of the formats (`xml`, `yaml`, ...)."""
        cls.load_parser_implementations()
        return list(Parser.frontend_parsers or {})

    @classmethod
    def get_file_extensions(cls) -> set[str]:
        """The file name extensions this format reads (none for the abstract parser)."""
        return set()

    @classmethod
    def may_parse(cls, filename: str) -> bool:
        return any(filename.endswith('.' + extension) for extension in cls.get_file_extensions())

    @classmethod
    def get_parsers_from_filename(cls, filename: str) -> list[type['Parser']]:
        cls.load_parser_implementations()
        return [parser for parser in (Parser.frontend_parsers or {}).values() if parser.may_parse(filename)]

    @classmethod
    def is_filename_valid(cls, filename: str) -> bool:
        return bool(cls.get_parsers_from_filename(filename))

    @classmethod
    def get_file_extensions_from_parsers(cls) -> set[str]:
        cls.load_parser_implementations()
        return {ext for parser in (Parser.frontend_parsers or {}).values() for ext in parser.get_file_extensions()}

    # -- reading ----------------------------------------------------------------------------------
    @classmethod
    def load(cls, file: str | os.PathLike | TextIO) -> tuple[Entity, 'Parser']:
        """The root entity of a launch file (a path or an open text file) and the parser for it.

        The formats whose extensions match the file name are tried first, then the others.

        Raises:
            InvalidFrontendLaunchFileError: no format could read it (with each one's reason).
        """
        cls.load_parser_implementations()
        path, text = read_file(file)
        candidates = cls.get_parsers_from_filename(path)
        candidates += [p for p in (Parser.frontend_parsers or {}).values() if p not in candidates]
        errors: list[Exception] = []
        for implementation in candidates:
            try:
                return implementation.load(_Named(text, path))
            except Exception as exc:   # the next format may read it; all reasons are reported
                errors.append(exc)
        extension = os.path.splitext(path)[1][1:] if cls.is_filename_valid(path) else ''
        raise InvalidFrontendLaunchFileError(extension, likely_errors=errors)

    # -- entities -> actions ----------------------------------------------------------------------
    def parse_description(self, entity: Entity) -> 'LaunchDescription':
        """The launch description of a root `launch` entity (its `deprecated` attribute is kept).

        Raises:
            LaunchFileError: the root is not `launch`, or one of its tags is wrong.
        """
        from zros.launch.launch_description import LaunchDescription
        if entity.type_name != 'launch':
            raise LaunchFileError(None, f'{entity.path}:{entity.line}: the root element of a launch file '
                                        f'must be <launch>, got <{entity.type_name}>')
        deprecated = entity.get_attr('deprecated', optional=True)
        return LaunchDescription(self.parse_actions(entity.children), deprecated_reason=deprecated)

    def parse_action(self, entity: Entity) -> 'Action':
        """The action of one entity, built by the parse method exposed for its tag.

        Raises:
            LaunchFileError: an unknown tag (naming the known ones), or whatever the tag's
                parse method finds wrong.
        """
        self.load_launch_extensions()
        parse = action_parse_methods.get(entity.type_name)
        if parse is None:
            raise entity.error(None, f"unknown tag (known tags: {', '.join(sorted(action_parse_methods))})")
        action_type, kwargs = parse(entity, self)
        return action_type(**kwargs)

    def parse_actions(self, entities: list[Entity]) -> list['Action']:
        return [self.parse_action(entity) for entity in entities]

    # -- text, as launch's actions' parse methods read it --------------------------------------
    def parse_substitution(self, value: str) -> list[Substitution]:
        """`value` as a list of substitutions (see zros.launch.frontend.parse_substitution)."""
        return parse_substitution(value)

    def parse_if_substitutions(self, value: Any) -> Any:
        return parse_if_substitutions(value)

    def escape_characters(self, value: str) -> str:
        return replace_escaped_characters(value)

    # -- typed attribute helpers for actions' parse methods ---------------------------------------
    @staticmethod
    def text(entity: Entity, key: str, *, optional: bool = False, data_type: Any = str) -> Text | None:
        """A string attribute with substitutions, parsed (syntax errors name the key)."""
        value = entity.get_attr(key, data_type=data_type, optional=optional)
        if value is None:
            return None
        return Text.parse(value, entity.origin_of(key))

    @staticmethod
    def typed(entity: Entity, key: str, data_type: type, *, optional: bool = True) -> Typed | None:
        """A bool/int/float attribute, given as a YAML value or a string with substitutions."""
        value = entity.get_attr(key, data_type=Any, optional=optional)
        if value is None:
            return None
        return Typed.from_yaml(value, data_type, entity.origin_of(key))


class _Named(io.StringIO):
    """A file's text with its name, so entities name the file in errors."""

    def __init__(self, text: str, name: str) -> None:
        super().__init__(text)
        self.name = name
