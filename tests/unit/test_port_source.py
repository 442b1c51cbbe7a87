"""zros.porting.port_source: the edits `zros port` makes to an rclpy program, on the text alone
(`zros port` and `zros python` as commands: tests/integration/test_porting.py)."""
from __future__ import annotations

import importlib
import sys
import textwrap

from zros.import_hook import module_target
from zros.porting import port_source

ROS_TALKER = textwrap.dedent('''\
    import sys
    import rclpy  # the client library
    from rclpy.node import Node
    from rclpy.executors import ExternalShutdownException
    from rclpy.qos import (QoSProfile,  # a comment inside the import stays
                           ReliabilityPolicy)
    from std_msgs.msg import String


    class Talker(Node):
        def __init__(self):
            super().__init__('ported_talker')
            self.declare_parameter('rate', 20.0)
            self.pub = self.create_publisher(String, 'ported', QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE))
            self.create_timer(1.0 / self.get_parameter('rate').value, self.tick)
            self.count = 0

        def tick(self):
            self.count += 1
            self.pub.publish(String(data='rclpy says %d' % self.count))


    def main(args=None):
        try:
            with rclpy.init(args=args):
                rclpy.spin(Talker())
        except (KeyboardInterrupt, ExternalShutdownException):
            pass


    if __name__ == '__main__':
        main(sys.argv)
''')


def test_port_source_rewrites_imports_and_keeps_the_rest():
    ported, notes = port_source(ROS_TALKER)
    assert 'import zros  # the client library' in ported
    assert 'from zros.executors import ExternalShutdownException' in ported
    assert 'from zros.qos import (QoSProfile,  # a comment inside the import stays\n' in ported
    assert 'from interfaces.std_msgs.msg import String' in ported
    assert 'with zros.init(args=args):' in ported and 'zros.spin(Talker())' in ported
    assert 'rclpy' not in ported.replace("'rclpy says %d'", '')
    assert not notes
    assert port_source(ported) == (ported, []), 'porting is idempotent'


def test_port_source_binds_the_names_the_code_uses():
    source = textwrap.dedent('''\
        import tf2_ros, os
        import tf2_ros.transform_listener
        import std_msgs.msg
        import sensor_msgs.point_cloud2 as pc2
        from launch import LaunchDescription
        from my_robot_interfaces.srv import Calibrate
        import numpy as np
        import logging
        x = "import rclpy"  # rclpy in strings and comments stays
    ''')
    ported, notes = port_source(source)
    assert ported.splitlines()[:8] == [
        'from zros import tf2_ros', 'import os',
        'import zros.tf2_ros.transform_listener', 'from zros import tf2_ros',
        'import interfaces.std_msgs.msg', 'from interfaces import std_msgs',
        'import zros.sensor_msgs_py.point_cloud2 as pc2',
        'from zros.launch import LaunchDescription']
    assert 'from interfaces.my_robot_interfaces.srv import Calibrate' in ported
    assert 'import numpy as np\nimport logging\nx = "import rclpy"  # rclpy in strings' in ported
    assert any("no 'my_robot_interfaces' interfaces" in n.text and n.line == 6 for n in notes), notes
    assert module_target('logging') == 'zros.logging' and module_target('logging', lambda top: True) is None


def test_a_bare_folder_named_like_a_ros_library_does_not_hide_zros(tmp_path, monkeypatch):
    """launch's own test folder holds a `launch/` directory with no __init__.py; on sys.path it
    is a namespace package, not an installed launch, so `launch` still means zros.launch."""
    from zros.import_hook import RosModuleFinder
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.delitem(sys.modules, 'launch_xml', raising=False)
    (tmp_path / 'launch_xml').mkdir()
    spec = RosModuleFinder().find_spec('launch_xml')
    assert spec is not None and spec.loader._target == 'zros.launch_xml'
    (tmp_path / 'launch_xml' / '__init__.py').write_text('')  # a real package is left alone
    importlib.invalidate_caches()
    assert RosModuleFinder().find_spec('launch_xml') is None
