"""XML launch files (`*.launch.xml`): the entity reader, launch_xml's value typing, one-line errors
with file and line, includes across the three front ends (checked through `resolve()`). XML files run by `zros
launch`: tests/integration/test_launch_xml_run.py.

The shipped examples' XML twins are checked against YAML and Python in
tests/integration/test_launch_python.py.
"""
from __future__ import annotations

import re
from dataclasses import replace
from pathlib import Path

import pytest

from unit.test_launch_parse import assert_located, error_of, only_process, plan_maker, processes, write  # noqa: F401 - fixture
from unit.test_launch_python_plans import normalized_plan
from zros.launch import resolve
from zros.launch.entity import Entity
from zros.launch.errors import LaunchFileError
from zros.launch.plan import GeneratedParams, ParamsFile
from zros.launch.xml_entity import XmlEntity, load_xml, load_xml_entities


@pytest.fixture
def plan_of(write, tmp_path: Path):
    """`plan_of(xml_text, name=value...)` -> the resolved Plan of a one-file XML launch."""
    return plan_maker(write, tmp_path, 'test.launch.xml')


def only_params(plan) -> dict:
    (generated,) = [p for p in only_process(plan).params if isinstance(p, GeneratedParams)]
    return generated.document['/**']['ros__parameters']


# -- the reader ---------------------------------------------------------------------------------
def test_xml_keeps_lines_of_elements_and_attributes():
    root = load_xml('f.xml', '<?xml version="1.0"?>\n<launch>\n  <node pkg="a"\n        exec="b"\n'
                             '        name="c">\n    <remap from="x" to="y"/>\n  </node>\n</launch>\n')
    (node,) = root.children
    assert (root.tag, root.line, node.tag, node.line) == ('launch', 2, 'node', 3)
    assert node.attributes == {'pkg': 'a', 'exec': 'b', 'name': 'c'}
    assert node.attribute_lines == {'pkg': 3, 'exec': 4, 'name': 5}
    assert node.children[0].line == 6


def test_entity_reads_attributes_children_and_lists(tmp_path: Path):
    (group, node) = load_xml_entities('f.xml', '<launch>\n<group scoped="false"><keep name="a" value="1"/>'
                                               '<log message="hi"/></group>\n'
                                               '<node pkg="p" exec="e" respawn="true" rate="1,2" rate-sep=",">'
                                               '<remap from="a" to="b"/><remap from="c" to="d"/></node>\n</launch>')
    assert isinstance(group, XmlEntity) and group.line == 2
    assert [k.get_attr('name') for k in group.get_attr('keep', data_type=list[Entity])] == ['a']
    assert [c.type_name for c in group.children] == ['log']       # `keep` was taken as a list
    assert group.get_attr('scoped', data_type=bool) is False
    assert node.get_attr('respawn', data_type=bool) is True
    assert node.get_attr('rate', data_type=list[str]) == ['1', '2']
    assert [(r.get_attr('from'), r.get_attr('to')) for r in node.get_attr('remap', data_type=list[Entity])] \
        == [('a', 'b'), ('c', 'd')]
    assert node.get_attr('pkg') == 'p' and node.get_attr('name', optional=True) is None
    with pytest.raises(LaunchFileError, match=r"^f\.xml:3: node: exec: expected an int, got a string 'e'$"):
        node.get_attr('exec', data_type=int)


def test_parameter_values_are_typed_as_launch_xml_types_them(plan_of):
    """The ROS 2 migration guide's type inference examples, and `type` forcing the text."""
    params = only_params(plan_of('''
        <launch>
          <arg name="rate" default="10"/>
          <node pkg="demo_nodes" exec="param_talker">
            <param name="a_string" value="'1'"/>
            <param name="an_int" value="1"/>
            <param name="a_float" value="1.0"/>
            <param name="another_string" value="asd"/>
            <param name="string_with_same_value_as_above" value="'asd'"/>
            <param name="quoted_string" value="\\'asd\\'"/>
            <param name="list_of_strings" value="asd, bsd, csd" value-sep=", "/>
            <param name="list_of_ints" value="1,2,3" value-sep=","/>
            <param name="another_list_of_strings" value="'1';'2';'3'" value-sep=";"/>
            <param name="strange_separator" value="'1'//'2'//'3'" value-sep="//"/>
            <param name="a_bool" value="true"/>
            <param name="from_var" value="$(var rate)"/>
            <param name="forced" value="1.50" type="str"/>
            <param name="group1">
              <param name="group2"><param name="my_param" value="1"/></param>
              <param name="another_param" value="2"/>
            </param>
          </node>
        </launch>'''))
    assert params == {
        'a_string': '1', 'an_int': 1, 'a_float': 1.0, 'another_string': 'asd',
        'string_with_same_value_as_above': 'asd', 'quoted_string': "'asd'",
        'list_of_strings': ['asd', 'bsd', 'csd'], 'list_of_ints': [1, 2, 3],
        'another_list_of_strings': ['1', '2', '3'], 'strange_separator': ['1', '2', '3'],
        'a_bool': True, 'from_var': 10, 'forced': '1.50',
        'group1': {'group2': {'my_param': 1}, 'another_param': 2}}


def test_every_tag_in_xml(plan_of, write, monkeypatch):
    """The tags and attributes are launch's, spelled as in YAML; typed attributes take text."""
    monkeypatch.delenv('XML_TEST_ENV', raising=False)
    params = write('p.yaml', '/**:\n  ros__parameters:\n    from_file: 1\n')
    text = f'''
        <launch>
          <arg name="mode" default="fast" description="how">
            <choice value="fast"/>
            <choice value="slow"/>
          </arg>
          <let name="word" value="$(eval '1 + 1')"/>
          <set_env name="XML_TEST_ENV" value="set"/>
          <group>
            <push-ros-namespace namespace="robot"/>
            <set_remap from="/a" to="/b"/>
            <set_parameter name="scope_level" value="3"/>
            <node pkg="demo_nodes" exec="talker" name="t" respawn="true" respawn_delay="1.5"
                  args="--flag 'two words'" if="$(equals $(var mode) fast)">
              <param from="{params}"/>
              <env name="EXTRA" value="$(env XML_TEST_ENV)"/>
            </node>
          </group>
          <node pkg="demo_nodes" exec="listener" unless="true"/>
          <executable cmd="echo $(var word)" name="echoer" output="screen"/>
          <timer period="2"><log message="later $(find-pkg-share demo_nodes)"/></timer>
        </launch>'''
    plan = plan_of(text)
    talker, echoer = processes(plan)
    assert talker.node.namespace == '/robot' and talker.respawn and talker.respawn_delay == 1.5
    assert ('EXTRA', 'set') in talker.env
    assert '--flag' in talker.cmd_head and 'two words' in talker.cmd_head
    assert ParamsFile(str(params.resolve())) in talker.params
    assert any(isinstance(p, GeneratedParams) and p.document['/**']['ros__parameters'] == {'scope_level': 3}
               for p in talker.params)
    assert '/a:=/b' in talker.cmd_head
    assert echoer.cmd_head[-1] == '2' and echoer.output == 'screen'
    assert 'after 2 s:' in plan.describe() and 'nodes/demo_nodes' in plan.describe()
    assert [p.label for p in processes(plan_of(text, mode='slow'))] == ['echoer']


# -- errors: one line, file and line --------------------------------------------------------------
@pytest.mark.parametrize('text, line, tag, key, reason', [
    ('<launch>\n  <node pkg="a" exec="b">\n</launch>\n', 3, None, None, 'invalid XML: mismatched tag'),
    ('<launch>\n<node pkg="a" pkg="b"/>\n</launch>\n', 2, None, None, 'invalid XML: duplicate attribute'),
    ('', 1, None, None, 'invalid XML: no element found'),
    ('<robot>\n</robot>\n', 1, None, None, 'the root element of a launch file must be <launch>, got <robot>'),
    ('<launch>\n  <frobnicate/>\n</launch>\n', 2, 'frobnicate', None, 'unknown tag (known tags: append_env, arg,'),
    ('<launch>\n  <node pkg="demo_nodes"\n        exec="talker"\n        colour="red"/>\n</launch>\n',
     4, 'node', 'colour', "unknown attribute 'colour' of `node` (known: args, cwd,"),
    ('<launch>\n  <node pkg="demo_nodes" exec="talker">\n    <remapp from="a" to="b"/>\n  </node>\n</launch>\n',
     3, 'node', 'remapp', 'unknown child element <remapp> of `node` (known: env, param, remap)'),
    ('<launch>\n  <node pkg="demo_nodes" exec="talker">\n    <remap from="a" too="b"/>\n  </node>\n</launch>\n',
     3, 'remap', None, "missing required attribute 'to'"),
    ('<launch>\n  <node pkg="demo_nodes" exec="talker"\n     respawn_delay="soon"/>\n</launch>\n',
     3, 'node', 'respawn_delay', "expected a number, got string 'soon'"),
    ('<launch>\n  <node pkg="demo_nodes" exec="talker" respawn="maybe"/>\n</launch>\n',
     2, 'node', 'respawn', "expected a bool (true or false), got string 'maybe'"),
    ('<launch>\n  <node pkg="demo_nodes" exec="talker" remap="a"/>\n</launch>\n',
     2, 'node', 'remap', "'remap' is written as child elements <remap .../>, not as an attribute"),
    ('<launch>\n  <node pkg="demo_nodes" exec="talker">\n    <param name="x" value="1" type="complex"/>\n'
     '  </node>\n</launch>\n', 3, 'param', 'type', 'expected one of str, int,'),
    ('<launch>\n  <node pkg="demo_nodes" exec="talker">\n    <param name="x" value="1,2" value-sep=""/>\n'
     '  </node>\n</launch>\n', 3, 'param', 'value-sep', 'the separator is empty'),
    ('<launch>\n  <log message="$(var nope)"/>\n</launch>\n', 2, 'log', 'message', "launch configuration 'nope'"),
    ('<launch>\n  <log message="$(frob)"/>\n</launch>\n', 2, 'log', 'message', "unknown substitution 'frob'"),
])
def test_errors_name_file_line_tag_and_attribute(plan_of, text: str, line: int, tag: str | None,
                                                key: str | None, reason: str):
    message = error_of(plan_of, text)
    if tag is None:
        assert re.match(rf'^\S*test\.launch\.xml:{line}: ', message), message
    else:
        assert_located(message, 'test.launch.xml', line, tag, key)
    assert reason in message, message


# -- includes across front ends, and the ROS 2 guide's example -------------------------------------
PY_INCLUDES_XML = '''
import os

from launch import LaunchDescription
from launch.actions import IncludeLaunchDescription
from launch.launch_description_sources import AnyLaunchDescriptionSource
from launch_xml.launch_description_sources import XMLLaunchDescriptionSource


def generate_launch_description():
    here = os.path.dirname(__file__)
    return LaunchDescription([
        IncludeLaunchDescription(XMLLaunchDescriptionSource(os.path.join(here, 'leaf.launch.xml')),
                                 launch_arguments={'who': 'python'}.items()),
        IncludeLaunchDescription(AnyLaunchDescriptionSource(os.path.join(here, 'leaf.launch.xml')),
                                 launch_arguments={'who': 'any'}.items()),
    ])
'''

LEAF_XML = '''
<launch>
  <arg name="who"/>
  <node pkg="demo_nodes" exec="talker" name="talker_$(var who)"/>
</launch>
'''

LEAF_PY = '''
from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument
from launch.substitutions import LaunchConfiguration
from launch_ros.actions import Node


def generate_launch_description():
    return LaunchDescription([
        DeclareLaunchArgument('who'),
        Node(package='demo_nodes', executable='listener', name=['listener_', LaunchConfiguration('who')]),
    ])
'''


def test_python_includes_xml(write, tmp_path: Path):
    write('leaf.launch.xml', LEAF_XML)
    plan = resolve(str(write('main.launch.py', PY_INCLUDES_XML)), log_dir=str(tmp_path / 'log'))
    assert [p.node.name for p in processes(plan)] == ['talker_python', 'talker_any']


def test_xml_includes_python_yaml_and_xml(write, tmp_path: Path):
    write('leaf.launch.py', LEAF_PY)
    write('leaf.launch.xml', LEAF_XML)
    write('leaf.launch.yaml', 'launch:\n- arg: {name: who}\n- log: {message: yaml got $(var who)}\n')
    main = write('main.launch.xml', '''
        <launch>
          <include file="leaf.launch.py"><arg name="who" value="py"/></include>
          <include file="$(dirname)/leaf.launch.yaml"><arg name="who" value="yaml"/></include>
          <group>
            <push_ros_namespace namespace="inner"/>
            <include file="leaf.launch.xml"><arg name="who" value="xml"/></include>
          </group>
        </launch>''')
    plan = resolve(str(main), log_dir=str(tmp_path / 'log'))
    assert [(p.node.name, p.node.namespace) for p in processes(plan)] == [('listener_py', '/'), ('talker_xml', '/inner')]
    assert 'yaml got yaml' in plan.describe()


GUIDE = Path(__file__).resolve().parents[1] / 'launch_guide'


def guide_plan(plan) -> str:
    """A `--print` plan without file names; the guide's Python tab pushes the literal namespace
    'chatter_py_ns' where XML and YAML push the argument's value 'chatter/py/ns'."""
    text = re.sub(r'\S+_launch\.(py|yaml|xml)(:\d+)?', 'FILE', normalized_plan(plan.describe()))
    return re.sub(r'/chatter_(py|xml|yaml)_ns\b', r'/chatter/\1/ns', text)


def test_the_ros2_guide_example_gives_one_plan_in_xml_yaml_and_python(tmp_path: Path):
    """"Using XML, YAML, and Python for ROS 2 Launch Files", its three tabs as printed: each
    includes demo_nodes_cpp's talker_listener launch file in all three formats."""
    plans = {ext: resolve(str(GUIDE / f'example_launch.{ext}'), launch_arguments={'background_r': '255'},
                          log_dir=str(tmp_path / 'log')) for ext in ('xml', 'yaml', 'py')}
    xml = plans['xml']
    assert guide_plan(plans['yaml']) == guide_plan(xml)
    assert [replace(e, origin=None) for e in plans['yaml'].effects] == [replace(e, origin=None) for e in xml.effects]
    assert guide_plan(plans['py']) == guide_plan(xml)
    nodes = [(p.node.namespace, p.node.name or p.node.executable) for p in processes(xml)]
    assert nodes == [('/', 'talker'), ('/', 'listener'),
                     ('/chatter/py/ns', 'talker'), ('/chatter/py/ns', 'listener'),
                     ('/chatter/xml/ns', 'talker'), ('/chatter/xml/ns', 'listener'),
                     ('/chatter/yaml/ns', 'talker'), ('/chatter/yaml/ns', 'listener'),
                     ('/turtlesim1', 'sim'), ('/turtlesim2', 'sim'), ('/', 'mimic')]
    second_sim = processes(xml)[9]
    (generated,) = [p for p in second_sim.params if isinstance(p, GeneratedParams)]
    assert generated.document['/**']['ros__parameters'] == {'background_r': 255, 'background_g': 255, 'background_b': 0}
    mimic = processes(xml)[10]
    assert '/input/pose:=/turtlesim1/turtle1/pose' in mimic.cmd_head


# -- a real run ----------------------------------------------------------------------------------
