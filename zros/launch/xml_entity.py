"""XML launch files as entities, so the one `Parser` builds the same actions from them as from YAML.

launch_xml reads a file with ElementTree, which forgets where things were written. Here a small
expat reader keeps the line of every element and of every attribute (attributes of one tag are
often written on lines of their own), so every error is `file:line: <tag>: <attribute>: reason`,
as it is for YAML.

The XML front end differs from the YAML one only in how values are written, as in ROS 2:
- an element's attributes are its keys; list keys (`param`, `remap`, `env`, `arg`, `choice`,
  `keep`, `composable_node`, `extra_arg`) are child elements of that name, and the children of
  `group` / `timer` are the remaining child elements;
- every attribute value is text. A string attribute is the text itself; where launch_xml types
  a value by YAML rules (a `param` `value`, a bool/int/float attribute such as `respawn`), the
  text is typed the same way (`1` int, `1.0` float, `true` bool, `'1'` the string 1), and
  `NAME-sep="SEP"` splits attribute NAME into a list first (`value="1,2,3" value-sep=","`).
"""
from __future__ import annotations

import re
from typing import Any, NamedTuple
from xml.parsers import expat

from zros.launch.entity import Entity, Scalar, checked_value, normalized_type
from zros.launch.errors import LaunchFileError, Origin

__all__ = ['XmlElement', 'XmlEntity', 'load_xml', 'load_xml_entities', 'load_xml_root']


class XmlElement(NamedTuple):
    """One element: its tag, attributes in the order written, and 1-based lines."""

    tag: str
    attributes: dict[str, str]
    line: int
    attribute_lines: dict[str, int]
    children: list['XmlElement']


def _attribute_lines(data: bytes, start: int, line: int, names: list[str]) -> dict[str, int]:
    """The line of each attribute of the start tag that begins at byte `start` on `line`."""
    end = data.find(b'>', start)
    tag = data[start:end if end >= 0 else len(data)]
    lines = {}
    for name in names:
        match = re.search(rb'\s' + re.escape(name.encode()) + rb'\s*=', tag)
        lines[name] = line + (tag.count(b'\n', 0, match.start() + 1) if match else 0)
    return lines


def load_xml(path: str, text: str) -> XmlElement:
    """The root element of an XML document; LaunchFileError `file:line: invalid XML: ...`."""
    data = text.encode('utf-8')
    parser = expat.ParserCreate()
    stack: list[XmlElement] = []
    roots: list[XmlElement] = []

    def start(tag: str, attributes: dict[str, str]) -> None:
        line = parser.CurrentLineNumber
        element = XmlElement(tag, attributes, line,
                             _attribute_lines(data, parser.CurrentByteIndex, line, list(attributes)), [])
        (stack[-1].children if stack else roots).append(element)
        stack.append(element)

    def end(tag: str) -> None:
        stack.pop()

    parser.StartElementHandler = start
    parser.EndElementHandler = end
    try:
        parser.Parse(data, True)
    except expat.ExpatError as exc:
        raise LaunchFileError(None, f'{path}:{exc.lineno}: invalid XML: {expat.ErrorString(exc.code)}') from None
    return roots[0]


def _yaml_typed(text: str) -> Any:
    """launch_xml's typing of a value: by YAML rules when that gives a scalar or a list of
    scalars, the text itself otherwise (`$(var x)`, `a: b`, an empty value)."""
    from zros.parameter import parse_parameter_value
    value = parse_parameter_value(text)
    scalar = (str, int, float, bool)
    if isinstance(value, scalar) or (isinstance(value, list) and all(isinstance(v, scalar) for v in value)):
        return value
    return text


class XmlEntity(Entity):
    """One element of an XML launch file, read through the YAML `Entity`'s interface.

    Constructed by `load_xml_entities` and by `get_attr(..., data_type=list[Entity])`.
    """

    def __init__(self, element: XmlElement, *, path: str, parent: Entity | None = None) -> None:
        super().__init__(element.tag, element, path=path, line=element.line, parent=parent)
        self._element = element
        self._claimed: set[str] = set()   # child tags a parser took, as a list or as children
        self._asked_children: set[str] = set()   # child tags a parser looked for

    def key_line(self, key: str) -> int:
        if key in self._element.attribute_lines:
            return self._element.attribute_lines[key]
        return next((child.line for child in self._element.children if child.tag == key), self.line)

    @property
    def is_mapping(self) -> bool:
        return True

    @property
    def keys(self) -> list[str]:
        return [*self._element.attributes, *dict.fromkeys(child.tag for child in self._element.children)]

    def has(self, name: str) -> bool:
        self._asked.add(name)
        return name in self._element.attributes or any(c.tag == name for c in self._element.children)

    @property
    def children(self) -> list[Entity]:
        """The child elements no parser took as a list (`keep` of a `group` is not a child)."""
        found = [c for c in self._element.children if c.tag not in self._claimed]
        self._claimed.update(c.tag for c in found)
        return [XmlEntity(c, path=self.path, parent=self) for c in found]

    def get_attr(self, name: str, *, data_type: Any = str, optional: bool = False,
                 tags: bool = False, can_be_str: bool = False) -> Any:
        """Attribute `name` as `data_type`; with `list[Entity]`, the child elements `<name>`.

        `str` and `Scalar` give the text as written; `bool`, `int`, `float`, `list[str]` and
        `Any` give it typed by YAML rules, split at `NAME-sep` first when there is one. With
        `can_be_str`, text that is not of `data_type` is returned as text instead of refused.

        Raises:
            LaunchFileError: missing required attribute or child, or a value of the wrong type.
        """
        data_type = normalized_type(data_type)
        self._asked.add(name)
        attributes = self._element.attributes
        if data_type == list[Entity]:
            self._asked_children.add(name)
            if name in attributes:
                raise self.error(name, f"'{name}' is written as child elements <{name} .../>, not as an attribute")
            items = [c for c in self._element.children if c.tag == name]
            if not items:
                if optional:
                    return None
                raise self.error(None, f'missing required child element <{name}>')
            self._claimed.add(name)
            return [XmlEntity(item, path=self.path, parent=self) for item in items]
        if name not in attributes:
            if optional:
                return None
            raise self.error(None, f"missing required attribute '{name}'")
        self._read.add(name)
        text = attributes[name]
        origin = self.origin_of(name)
        if data_type is str or data_type is Scalar:
            return text
        separator = f'{name}-sep'
        if separator in attributes:
            self._read.add(separator)
            if not attributes[separator]:
                raise self.error(separator, 'the separator is empty')
            items = text.split(attributes[separator])
            value = [item if data_type == list[str] else _yaml_typed(item) for item in items]
        else:
            value = _yaml_typed(text)
        if can_be_str and isinstance(value, str):
            return value   # launch's option: text (with substitutions) stands for any type
        return checked_value(value, data_type, origin)

    def raw(self, name: str) -> Any:
        return self.get_attr(name, data_type=Any, optional=True)

    def assert_complete(self) -> None:
        """Raise for the first attribute or child element that no parser read."""
        tag = f'`{self.type_name}`'   # launch_xml's errors name the tag this way
        for name in self._element.attributes:
            if name not in self._read:
                raise self.error(name, f"unknown attribute '{name}' of {tag}{_known(self._asked - self._asked_children)}")
        for child in self._element.children:
            if child.tag not in self._claimed:
                raise LaunchFileError(Origin(self.path, child.line, self.type_name, child.tag),
                                      f'unknown child element <{child.tag}> of {tag}{_known(self._asked_children)}')


def _known(names: set[str]) -> str:
    return f" (known: {', '.join(sorted(names))})" if names else ''


def load_xml_entities(path: str, text: str) -> list[XmlEntity]:
    """The child elements of the root element."""
    return load_xml_root(path, text).children


def load_xml_root(path: str, text: str) -> XmlEntity:
    """The root element of an XML file, whatever its tag (`Parser.parse_description` wants
    `<launch>`; launch_xml reads other documents' entities too)."""
    return XmlEntity(load_xml(path, text), path=path)
