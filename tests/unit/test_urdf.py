"""Robot descriptions: URDF parsing and its errors, xacro (with `$(find pkg)` through zros's
package lookup) and the TurtleBot3 burger model. The `xacro` command and robot_state_publisher
as processes: tests/integration/test_urdf_processes.py."""
from __future__ import annotations

import math
import textwrap

import numpy as np
import pytest

from conftest import REPO
from zros.urdf import Box, Cylinder, URDFError, load_urdf, parse_urdf
from zros.urdf.xacro import XacroError, process_file

BURGER = REPO / 'nodes' / 'turtlebot3_description' / 'urdf' / 'turtlebot3_burger.urdf'

TWO_WHEELER = textwrap.dedent('''\
    <?xml version="1.0"?>
    <robot name="two_wheeler" xmlns:xacro="http://www.ros.org/wiki/xacro">
      <xacro:arg name="track" default="0.2"/>
      <xacro:property name="radius" value="0.05"/>
      <xacro:include filename="$(find turtlebot3_description)/urdf/turtlebot3_burger.urdf" ns="unused"/>
      <xacro:macro name="wheel" params="side y">
        <joint name="${side}_wheel_joint" type="continuous">
          <parent link="base_link"/>
          <child link="${side}_wheel"/>
          <origin xyz="0 ${y} ${radius}" rpy="0 0 0"/>
          <axis xyz="0 1 0"/>
        </joint>
        <link name="${side}_wheel">
          <visual><geometry><cylinder radius="${radius}" length="0.02"/></geometry></visual>
        </link>
      </xacro:macro>
      <link name="base_link">
        <collision><geometry><box size="0.3 0.2 0.1"/></geometry></collision>
      </link>
      <xacro:wheel side="left" y="${$(arg track) / 2}"/>
      <xacro:wheel side="right" y="${-$(arg track) / 2}"/>
      <joint name="laser_joint" type="fixed">
        <parent link="base_link"/>
        <child link="laser"/>
        <origin xyz="0.1 0 0.2" rpy="0 0 ${pi}"/>
      </joint>
      <link name="laser"/>
    </robot>
    ''')


def test_turtlebot3_burger_model():
    robot = load_urdf(BURGER)
    assert robot.name == 'turtlebot3_burger' and robot.root == 'base_footprint'
    assert {j.name: j.type for j in robot.joints.values()} == {
        'base_joint': 'fixed', 'wheel_left_joint': 'continuous', 'wheel_right_joint': 'continuous',
        'caster_back_joint': 'fixed', 'imu_joint': 'fixed', 'scan_joint': 'fixed'}
    poses = robot.link_poses()
    assert poses['base_scan'][:3] == pytest.approx((-0.032, 0.0, 0.182))     # lidar plane 0.182 m up
    assert poses['wheel_left_link'][1] == pytest.approx(0.080)
    wheel = robot.links['wheel_left_link'].collisions[0].geometry
    assert isinstance(wheel, Cylinder) and (wheel.radius, wheel.length) == (0.033, 0.018)
    assert isinstance(robot.links['base_link'].visuals[0].geometry, Box)
    assert robot.links['base_link'].visuals[0].material.rgba == (0.6, 0.6, 0.6, 1.0)
    outline = robot.footprint('base_footprint')
    assert outline[:, 0].min() == pytest.approx(-0.102, abs=1e-3) and outline[:, 0].max() == pytest.approx(0.038, abs=1e-3)
    assert np.abs(outline[:, 1]).max() == pytest.approx(0.089, abs=1e-3)     # the wheels stick out
    assert np.hypot(outline[:, 0], outline[:, 1]).max() == pytest.approx(0.124, abs=2e-3)


def test_joint_motion():
    robot = parse_urdf('<robot name="r"><link name="a"/><link name="b"/><link name="c"/>'
                       '<joint name="spin" type="continuous"><parent link="a"/><child link="b"/>'
                       '<origin xyz="1 0 0"/><axis xyz="0 0 2"/></joint>'
                       '<joint name="slide" type="prismatic"><parent link="b"/><child link="c"/>'
                       '<axis xyz="1 0 0"/><limit lower="0" upper="1" effort="1" velocity="1"/></joint></robot>')
    poses = robot.link_poses({'spin': math.pi / 2, 'slide': 0.5})
    assert poses['c'][:3] == pytest.approx((1.0, 0.5, 0.0))
    assert 2 * math.atan2(poses['c'][5], poses['c'][6]) == pytest.approx(math.pi / 2)


@pytest.mark.parametrize('text, fragment', [
    ('', 'empty'),
    ('<robot name="r"><link name="a"></robot>', 'not well-formed XML: mismatched tag: line 1'),
    ('<robot name="r"><link name="a"/><joint name="j" type="fixed"><parent link="a"/></joint></robot>',
     '<joint name=\'j\'>: missing <child link="..."/>'),
    ('<robot name="r"><link name="a"/><joint name="j" type="hinge"><parent link="a"/><child link="a"/></joint></robot>',
     "<joint name='j'>: type 'hinge' is not one of"),
    ('<robot name="r"><link name="a"/><link name="b"/><joint name="j" type="fixed"><parent link="a"/>'
     '<child link="c"/></joint></robot>', "<joint name='j'>: link 'c' is not defined"),
    ('<robot name="r"><link name="a"><visual><geometry><box size="1 2"/></geometry></visual></link></robot>',
     "<link name='a'> <visual> <box>: size='1 2' must have 3 number(s)"),
    ('<robot name="r"><link name="a"/><link name="b"/></robot>', 'roots are a, b'),
    ('<robot name="r"><link name="a"/><link name="b"/><joint name="j" type="revolute"><parent link="a"/>'
     '<child link="b"/></joint></robot>', "<joint name='j'>: a revolute joint needs <limit"),
    ('<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro"><xacro:property name="a" value="1"/>'
     '<link name="a"/></robot>', 'run it through xacro first'),
])
def test_malformed_urdf_names_the_element(text, fragment):
    with pytest.raises(URDFError) as info:
        parse_urdf(text)
    assert fragment in str(info.value) and '\n' not in str(info.value)


def test_xacro_expands_macros_args_and_find(tmp_path):
    source = tmp_path / 'two_wheeler.urdf.xacro'
    source.write_text(TWO_WHEELER.replace('<xacro:include filename="$(find turtlebot3_description)/urdf/'
                                          'turtlebot3_burger.urdf" ns="unused"/>',
                                          '<xacro:property name="burger" value="$(find turtlebot3_description)"/>'))
    robot = parse_urdf(process_file(source, {'track': '0.4'}))
    assert robot.joints['left_wheel_joint'].origin.xyz == (0.0, 0.2, 0.05)
    assert robot.joints['right_wheel_joint'].origin.xyz == (0.0, -0.2, 0.05)
    assert robot.joints['laser_joint'].origin.rpy[2] == pytest.approx(math.pi)
    bad = tmp_path / 'bad.urdf.xacro'
    bad.write_text('<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro"><xacro:nosuch/></robot>')
    with pytest.raises(XacroError, match=r'bad\.urdf\.xacro: unknown macro name: xacro:nosuch'):
        process_file(bad)
    unknown_pkg = tmp_path / 'pkg.urdf.xacro'
    unknown_pkg.write_text('<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">'
                           '<xacro:include filename="$(find no_such_pkg)/x.xacro"/></robot>')
    with pytest.raises(XacroError, match=r"pkg\.urdf\.xacro: .*'no_such_pkg' not found"):
        process_file(unknown_pkg)
