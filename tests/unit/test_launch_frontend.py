"""launch.frontend over zros's launch model: the shared parser, exposing tags and substitutions."""
from __future__ import annotations

import io
import os
import warnings
from typing import List

import pytest

from zros.launch.actions import LogInfo, SetLaunchConfiguration
from zros.launch.context import LaunchContext
from zros.launch.entity import Entity
from zros.launch.errors import LaunchFileError
from zros.launch.files import load_launch_file
from zros.launch.frontend import InvalidFrontendLaunchFileError, Parser, expose_action, expose_substitution
from zros.launch.frontend import expose, parser as parser_module, type_utils
from zros.launch.frontend.formats import XmlParser, YamlParser
from zros.launch.frontend.parse_substitution import parse_if_substitutions, parse_substitution
from zros.launch.substitutions import EnvironmentVariable, Substitution, TextSubstitution
from zros.launch.xml_entity import XmlEntity


@pytest.fixture
def registries():
    """Tags and substitutions a test exposes are forgotten afterwards."""
    saved = dict(expose.action_parse_methods), dict(expose.substitution_parse_methods)
    yield
    for registry, before in zip((expose.action_parse_methods, expose.substitution_parse_methods), saved):
        registry.clear()
        registry.update(before)


class Shout(LogInfo):
    """A tag of a test's own: `<shout word="..."/>` logs the word in capitals."""

    @classmethod
    def parse(cls, entity, parser):
        _, kwargs = super(LogInfo, cls).parse(entity, parser)
        kwargs['msg'] = entity.get_attr('word').upper()
        return cls, kwargs


# -- Parser.load / parse_description --------------------------------------------------------------
def test_a_file_without_a_name_is_tried_in_each_format():
    root, parser = Parser.load(io.StringIO('<launch deprecated="old"><let name="a" value="1"/></launch>'))
    assert isinstance(parser, XmlParser) and root.type_name == 'launch'
    description = parser.parse_description(root)
    assert description.deprecated_reason == 'old'
    assert [type(a) for a in description.entities] == [SetLaunchConfiguration]

    root, parser = Parser.load(io.StringIO('launch:\n- let: {name: a, value: "1"}\n- log: {message: hi}\n'))
    assert isinstance(parser, YamlParser)
    assert [a.tag for a in parser.parse_description(root).entities] == ['let', 'log']


def test_a_path_picks_its_format_by_extension(tmp_path):
    path = tmp_path / 'x.launch.yaml'
    path.write_text('launch:\n- arg: {name: a}\n')
    root, parser = Parser.load(str(path))
    assert isinstance(parser, YamlParser) and root.path == str(path)
    assert Parser.get_available_extensions() == ['xml', 'yaml']
    assert Parser.is_filename_valid('a.launch.xml') and not Parser.is_filename_valid('a.launch.py')


def test_text_no_format_reads_names_each_formats_reason():
    with pytest.raises(InvalidFrontendLaunchFileError) as info:
        Parser.load(io.StringIO('just words'))
    assert 'invalid XML' in str(info.value) and "'launch:' list" in str(info.value)
    assert isinstance(info.value, ValueError)


def test_any_root_element_loads_but_only_launch_describes():
    root, parser = Parser.load(io.StringIO('<root><tag attr="1,2,3" attr-sep=","/></root>'))
    (tag,) = root.children
    assert tag.get_attr('attr', data_type=List[int]) == [1, 2, 3]
    assert tag.get_attr('attr', data_type=List[float]) == [1.0, 2.0, 3.0]
    with pytest.raises(LaunchFileError, match='root element of a launch file must be <launch>, got <root>'):
        parser.parse_description(root)


def test_an_unread_attribute_names_the_tag_as_launch_does():
    root, parser = Parser.load(io.StringIO('<launch>\n<arg name="a" whats_this="x"/>\n</launch>'))
    with pytest.raises(ValueError, match="unknown attribute 'whats_this' of `arg`"):
        parser.parse_description(root)


# -- expose_action -------------------------------------------------------------------------------
def test_an_exposed_class_is_a_tag_of_every_format(registries):
    expose_action('shout')(Shout)
    root, parser = Parser.load(io.StringIO('launch:\n- shout: {word: hey}\n'))
    (action,) = parser.parse_description(root).entities
    assert isinstance(action, Shout)
    root, parser = Parser.load(io.StringIO('<launch><shout word="hey" volume="11"/></launch>'))
    with pytest.raises(ValueError, match="unknown attribute 'volume' of `shout`"):
        parser.parse_description(root)   # the exposed parse is checked for leftovers, as built-ins are


def test_exposing_is_idempotent_but_a_name_has_one_owner(registries):
    expose_action('shout')(Shout)
    expose_action('shout')(Shout)   # the module imported a second time
    with pytest.raises(RuntimeError, match='Two action parsing methods exposed with the same name'):
        expose_action('shout')(LogInfo)
    with pytest.raises(RuntimeError, match='is not a callable or a class containing a parse method'):
        expose_action('five')(5)


def test_zros_own_tags_are_in_the_same_registry():
    Parser.load_launch_extensions()
    assert {'node', 'let', 'group', 'executable'} <= set(expose.action_parse_methods)


def test_a_failing_extension_is_a_warning(monkeypatch):
    class Broken:
        name = 'broken'

        def load(self):
            raise ImportError('nope')

    monkeypatch.setattr(parser_module.importlib_metadata, 'entry_points',
                        lambda: {'launch.frontend.launch_extension': [Broken()]})
    monkeypatch.setattr(Parser, 'extensions_loaded', False)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter('always')
        Parser.load_launch_extensions()
    assert any('Failed to load the launch extension: broken' in str(w.message) for w in caught)
    assert Parser.extensions_loaded


# -- substitutions -------------------------------------------------------------------------------
class Echo(Substitution):
    def __init__(self, text: str) -> None:
        self.text = text

    def perform(self, context) -> str:
        return self.text


def test_an_exposed_substitution_parses_in_launch_text(registries):
    @expose_substitution('echo')
    def parse_echo(data):
        return Echo, {'text': ''.join(s.perform(None) for s in data[0])}

    parts = parse_substitution('a_$(echo b)_$(env HOME x)')
    assert [type(p) for p in parts] == [TextSubstitution, Echo, TextSubstitution, EnvironmentVariable]
    assert parts[1].perform(None) == 'b'
    assert [s.perform(None) for s in parts[3].name] == ['HOME'] and parts[3].default_value[0].text == 'x'
    root, parser = Parser.load(io.StringIO('<launch><let name="v" value="$(echo hi)!"/></launch>'))
    (let,) = parser.parse_description(root).entities
    context = LaunchContext()
    let.visit(context)
    assert context.configurations['v'] == 'hi!'


def test_parse_if_substitutions_keeps_plain_values():
    assert parse_if_substitutions(1) == 1 and parse_if_substitutions('a') == 'a'
    assert parse_substitution('')[0].perform(None) == ''
    assert isinstance(parse_if_substitutions('$(env A)')[0], EnvironmentVariable)
    with pytest.raises(ValueError, match='non-uniform'):
        parse_if_substitutions(['$(env A)', 1, 1.0])


def test_type_identifiers():
    assert type_utils.get_data_type_from_identifier('list_of_int') == list[int]
    assert type_utils.check_is_list_entity(List[XmlEntity]) and not type_utils.check_is_list_entity(List[str])
    assert type_utils.check_is_list_entity(list[Entity])
    with pytest.raises(ValueError, match="invalid type identifier 'complex'"):
        type_utils.get_data_type_from_identifier('complex')


def test_zros_launch_reads_markup_through_the_parser(tmp_path, registries):
    expose_action('shout')(Shout)
    path = tmp_path / 'x.launch.xml'
    path.write_text('<launch>\n  <shout word="loud"/>\n</launch>\n')
    (action,) = load_launch_file(str(path))
    assert isinstance(action, Shout) and action.origin.line == 2


# -- parsed actions read as launch's ---------------------------------------------------------------
def test_a_text_attribute_reads_as_a_list_of_substitutions():
    root, parser = Parser.load(io.StringIO('<launch><log message="a $(env HOME) b"/>'
                                           '<append_env name="V" value="x" prepend="false"/></launch>'))
    log, append = parser.parse_description(root).entities
    assert [type(s) for s in log.msg] == [TextSubstitution, EnvironmentVariable, TextSubstitution]
    assert len(log.msg) == 3 and log.msg[0].perform(None) == 'a '
    assert not append.prepend   # a constant bool attribute is as true as its value
    assert [s.perform(None) for s in append.separator] == [os.pathsep]   # the default, as launch shows it


def test_an_empty_text_is_one_empty_substitution_and_still_written():
    root, parser = Parser.load(io.StringIO('<launch><log message=""/></launch>'))
    (log,) = parser.parse_description(root).entities
    assert [s.perform(None) for s in log.msg] == [''] and log.msg


def test_launch_frontend_module_names_are_the_same_objects():
    from zros.launch.frontend import entity as entity_module
    assert entity_module.Entity is Entity and issubclass(XmlEntity, entity_module.Entity)


def test_can_be_str_lets_text_stand_for_a_typed_value():
    root, _ = Parser.load(io.StringIO('launch:\n- t: {n: "$(var n)", m: 2}\n'))
    (tag,) = root.children
    assert tag.get_attr('n', data_type=int, can_be_str=True) == '$(var n)'
    assert tag.get_attr('m', data_type=None) == 2
    with pytest.raises(LaunchFileError, match="expected an int, got a string"):
        tag.get_attr('n', data_type=int)
    root, _ = Parser.load(io.StringIO('<launch><t n="$(var n)"/></launch>'))
    assert root.children[0].get_attr('n', data_type=float, can_be_str=True) == '$(var n)'
