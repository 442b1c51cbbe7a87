"""`zros port` (the porting edits, on files and package trees) and `zros python` (unmodified
rclpy programs run through the import hook). The edits on text alone: tests/unit/test_port_source.py."""
from __future__ import annotations

import sys
import textwrap

from conftest import assert_clean_failure
from unit.test_port_source import ROS_TALKER

from zros.import_hook import module_target
from zros.porting import port_source


ROS_LISTENER = textwrap.dedent('''\
    import rclpy
    from tf2_ros import Buffer  # numpy's first import, inside the hook
    import std_msgs.msg
    import sensor_msgs.point_cloud2 as pc2
    from sensor_msgs.msg import PointCloud2
    from cv_bridge import CvBridge


    def main():
        rclpy.init()
        node = rclpy.create_node('ported_listener')
        assert rclpy.Parameter('speed', value=2.0).type_ == rclpy.Parameter.Type.DOUBLE
        assert pc2.create_cloud_xyz32 and PointCloud2 and CvBridge and Buffer
        node.create_subscription(std_msgs.msg.String, 'ported',
                                 lambda msg: node.get_logger().info('heard ' + msg.data), 10)
        rclpy.spin(node)


    main()
''')


def test_zros_port_on_a_package_tree(tmp_path, zros_cli):
    package = tmp_path / 'my_pkg'
    (package / 'my_pkg').mkdir(parents=True)
    (package / 'my_pkg' / 'talker.py').write_text(ROS_TALKER)
    (package / 'setup.py').write_text('from setuptools import setup\nsetup(name="my_pkg")\n')
    (package / 'build' / 'lib').mkdir(parents=True)
    (package / 'build' / 'lib' / 'copy.py').write_text('import rclpy\n')
    dry = zros_cli('port', str(package), '--dry-run')
    assert dry.returncode == 0, dry
    assert '\n-import rclpy  # the client library\n' in dry.stdout and '\n+import zros  # the client library\n' in dry.stdout
    assert 'would port 1 file(s)' in dry.stderr and (package / 'my_pkg' / 'talker.py').read_text() == ROS_TALKER
    done = zros_cli('port', str(package))
    assert done.returncode == 0 and 'ported 1 file(s)' in done.stderr, done
    assert (package / 'my_pkg' / 'talker.py').read_text() == port_source(ROS_TALKER)[0]
    assert (package / 'build' / 'lib' / 'copy.py').read_text() == 'import rclpy\n'
    again = zros_cli('port', str(package))
    assert again.stdout == '' and 'ported 0 file(s)' in again.stderr


def test_zros_port_bad_input(tmp_path, zros_cli):
    assert_clean_failure(zros_cli('port', str(tmp_path / 'nope.py')), 'no such file or directory')
    broken = tmp_path / 'broken.py'
    broken.write_text('import rclpy\ndef f(:\n')
    result = zros_cli('port', str(broken))
    assert result.returncode == 1 and 'broken.py:2: cannot parse' in result.stderr, result
    assert 'Traceback' not in result.stderr and broken.read_text() == 'import rclpy\ndef f(:\n'


def test_unmodified_and_ported_programs_run(tmp_path, spawn, zros_cli):
    (tmp_path / 'listener.py').write_text(ROS_LISTENER)
    (tmp_path / 'talker.py').write_text(ROS_TALKER)
    listener = spawn(sys.executable, '-m', 'zros.cli.main', 'python', str(tmp_path / 'listener.py'), name='listener')
    spawn(sys.executable, '-m', 'zros.cli.main', 'python', str(tmp_path / 'talker.py'),
          '--ros-args', '-p', 'rate:=10.0', name='talker')
    listener.wait_for_output('heard rclpy says 1', timeout=20)
    ported = tmp_path / 'ported'
    ported.mkdir()
    (ported / 'talker.py').write_text(port_source(ROS_TALKER.replace("'ported'", "'ported2'"))[0])
    spawn(sys.executable, str(ported / 'talker.py'), name='ported_talker')
    echo = zros_cli('topic', 'echo', '/ported2', '--once', '--timeout', '15', timeout=30)
    assert echo.returncode == 0 and 'data: rclpy says' in echo.stdout, echo


def test_zros_run_loads_unmodified_rclpy_nodes(tmp_path, spawn, zros_cli, monkeypatch):
    (tmp_path / 'my_pkg').mkdir()
    (tmp_path / 'my_pkg' / 'talker.py').write_text(ROS_TALKER.replace("'ported'", "'from_node_path'"))
    monkeypatch.setenv('ZROS_NODE_PATH', str(tmp_path))
    spawn.node('my_pkg', 'talker')
    echo = zros_cli('topic', 'echo', '/from_node_path', '--once', '--timeout', '15', timeout=30)
    assert echo.returncode == 0 and 'data: rclpy says' in echo.stdout, echo


def test_zros_python_bad_input(tmp_path, zros_cli):
    assert_clean_failure(zros_cli('python', str(tmp_path / 'missing.py')), 'no such file')
    failing = tmp_path / 'exits.py'
    failing.write_text('import sys\nsys.exit(3)\n')
    assert zros_cli('python', str(failing)).returncode == 3


def test_zros_python_runs_a_packages_rclpy_tests(tmp_path, zros_cli):
    (tmp_path / 'test_speed.py').write_text(textwrap.dedent('''\
        import pytest
        import rclpy
        from rclpy.node import Node


        @pytest.fixture
        def node():
            rclpy.init()
            node = Node('speed_node')
            node.declare_parameter('speed', 1.0)
            yield node
            node.destroy_node()
            rclpy.shutdown()


        def test_speed(node):
            node.set_parameters([rclpy.Parameter('speed', value=2.0)])
            assert node.get_parameter('speed').value == 2.0
    '''))
    result = zros_cli('python', '-m', 'pytest', '-q', '-p', 'no:cacheprovider', str(tmp_path / 'test_speed.py'),
                      timeout=60)
    assert result.returncode == 0 and '1 passed' in result.stdout, result
    assert_clean_failure(zros_cli('python', '-m', 'no_such_module'), "no module named 'no_such_module'")


ONE_IMPORT_WORLD = textwrap.dedent('''\
    import sys
    import zros.import_hook
    zros.import_hook.install()
    import launch
    import launch.conditions, launch.action, launch.actions, launch_ros.actions
    import zros.launch.conditions, zros.launch.action
    from launch.conditions import IfCondition
    from launch_ros.actions import Node
    assert sys.modules['launch.conditions'] is zros.launch.conditions
    assert launch.action is zros.launch.action
    assert IfCondition is zros.launch.conditions.IfCondition
    Node(package='demo_nodes', executable='talker', condition=IfCondition('true'))
    import logging, numpy
    assert logging.__name__ == 'logging' and numpy.__name__ == 'numpy'
    print('one world')
''')


def test_the_hook_makes_one_module_of_each_ros_name(tmp_path):
    """`launch` imported first must not make `launch.conditions` a second copy of zros's file
    (a class would exist twice and zros's own type checks refuse it), and `launch.action` is
    launch's module, not an interface kind."""
    import subprocess
    script = tmp_path / 'one_world.py'
    script.write_text(ONE_IMPORT_WORLD)
    result = subprocess.run([sys.executable, script], capture_output=True, text=True, timeout=60)
    assert result.returncode == 0 and result.stdout == 'one world\n', result.stderr
    assert module_target('launch.action') == 'zros.launch.action'
    assert module_target('nav2_msgs.action') == 'interfaces.nav2_msgs.action'
