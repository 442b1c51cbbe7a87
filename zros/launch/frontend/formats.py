"""zros's two markup formats as `Parser`s: XML (launch_xml's) and YAML (launch_yaml's).

Each only knows how to read a file into its root `launch` entity; the entities then go through
the shared `Parser`, so both formats build the same actions with the same checks.
"""
from __future__ import annotations

import os
from typing import Callable, ClassVar, TextIO

from zros.launch.entity import Entity, load_launch_root
from zros.launch.frontend.parser import Parser, read_file
from zros.launch.xml_entity import load_xml_root

__all__ = ['XmlParser', 'YamlParser', 'BUILTIN_PARSERS']


class _Format(Parser):
    """A format: the file name extensions it claims and the function reading a file's root."""

    extensions: ClassVar[frozenset[str]] = frozenset()
    read_root: ClassVar[Callable[[str, str], Entity]]

    @classmethod
    def load(cls, file: str | os.PathLike | TextIO) -> tuple[Entity, Parser]:
        path, text = read_file(file)
        return cls.read_root(path, text), cls(path)

    @classmethod
    def get_file_extensions(cls) -> set[str]:
        return set(cls.extensions)


class XmlParser(_Format):
    """`.launch.xml` files (launch_xml.Parser)."""

    extensions = frozenset({'xml', 'launch'})
    read_root = staticmethod(load_xml_root)


class YamlParser(_Format):
    """`.launch.yaml` files (launch_yaml.Parser)."""

    extensions = frozenset({'yaml', 'yml'})
    read_root = staticmethod(load_launch_root)


#: format name -> parser, as `launch.frontend.parser` entry points would declare them.
BUILTIN_PARSERS: dict[str, type[Parser]] = {'xml': XmlParser, 'yaml': YamlParser}
