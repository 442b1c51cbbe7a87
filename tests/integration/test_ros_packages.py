"""ROS 2 packages as students write them (ament_python: package.xml, setup.py with data_files and
console_scripts), run with no colcon build: in a workspace on ZROS_NODE_PATH, `pip install -e`'d,
and from an install prefix's ament index. The course is seed 001's publisher_pkg walk."""
from __future__ import annotations

import os
import signal
import subprocess
import sys
from pathlib import Path

import pytest

from conftest import REPO, run_cli
from zros.ament_index_python.ros_packages import find_source_packages, read_setup_py, source_package

# seed 001, as printed: the node, its launch file, and the setup.py the course asks for
SIMPLE_PUBLISHER = '''import rclpy
from rclpy.node import Node
from geometry_msgs.msg import Twist

class SimplePublisher(Node):

    def __init__(self):
        super().__init__('simple_publisher')
        self.publisher_ = self.create_publisher(Twist, 'cmd_vel', 10)
        self.timer = self.create_timer(0.5, self.timer_callback)

    def timer_callback(self):
        msg = Twist()
        msg.linear.x = 0.5
        msg.angular.z = 0.5
        self.publisher_.publish(msg)
        self.get_logger().info('Publishing: "%s"' % msg)

def main(args=None):
    rclpy.init(args=args)
    simple_publisher = SimplePublisher()
    rclpy.spin(simple_publisher)
    simple_publisher.destroy_node()
    rclpy.shutdown()

if __name__ == '__main__':
    main()
'''

LAUNCH = '''from launch import LaunchDescription
from launch_ros.actions import Node

def generate_launch_description():
    return LaunchDescription([
        Node(
            package='publisher_pkg',
            executable='simple_publisher',
            output='screen'),
])
'''

SETUP_PY = '''from setuptools import setup
import os
from glob import glob

package_name = 'publisher_pkg'

setup(
    name=package_name,
    version='0.0.0',
    packages=[package_name],
    data_files=[
        ('share/ament_index/resource_index/packages',
            ['resource/' + package_name]),
        ('share/' + package_name, ['package.xml']),
        (os.path.join('share', package_name), glob('launch/*.launch.py'))
    ],
    install_requires=['setuptools'],
    zip_safe=True,
    maintainer='user',
    maintainer_email='user@todo.todo',
    description='TODO: Package description',
    license='TODO: License declaration',
    tests_require=['pytest'],
    entry_points={
        'console_scripts': [
            'simple_publisher = publisher_pkg.simple_publisher:main'
        ],
    },
)
'''


@pytest.fixture
def cache(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """Share trees of source packages go to the test's own folder."""
    monkeypatch.setenv('ZROS_CACHE_DIR', str(tmp_path / 'cache'))
    return tmp_path / 'cache'


def course_workspace(tmp_path: Path) -> Path:
    """~/ros2_ws after seed 001's steps: `ros2 pkg create --build-type ament_python publisher_pkg
    --dependencies rclpy std_msgs geometry_msgs` in src/, then the node, launch file and setup.py."""
    src = tmp_path / 'ros2_ws' / 'src'
    src.mkdir(parents=True)
    created = run_cli('pkg', 'create', '--build-type', 'ament_python', 'publisher_pkg', '--dependencies',
                      'rclpy', 'std_msgs', 'geometry_msgs', '--destination-directory', src)
    assert created.returncode == 0, created
    package = src / 'publisher_pkg'
    assert 'build type: ament_python' in created.stdout
    assert '<build_type>ament_python</build_type>' in (package / 'package.xml').read_text()
    assert (package / 'resource' / 'publisher_pkg').is_file() and (package / 'setup.cfg').is_file()
    (package / 'publisher_pkg' / 'simple_publisher.py').write_text(SIMPLE_PUBLISHER)
    (package / 'launch').mkdir()
    (package / 'launch' / 'publisher_pkg_launch_file.launch.py').write_text(LAUNCH)
    (package / 'setup.py').write_text(SETUP_PY)
    return tmp_path / 'ros2_ws'


def hears_the_publisher(command: list[str], env: dict[str, str], cwd: Path) -> str:
    """Start `command` (a node or a launch), echo one /cmd_vel, stop it with Ctrl-C; its output."""
    process = subprocess.Popen(command, cwd=cwd, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                               text=True, start_new_session=True)
    try:
        echoed = run_cli('topic', 'echo', '/cmd_vel', 'geometry_msgs/msg/Twist', '--once', '--timeout', '30',
                         timeout=40, env=env)
        assert echoed.returncode == 0 and 'x: 0.5' in echoed.stdout, echoed
    finally:
        os.killpg(process.pid, signal.SIGINT)
        output, _ = process.communicate(timeout=15)
    assert 'Traceback' not in output, output
    return output


# -- reading the package files, no processes ------------------------------------------------------
def test_setup_py_is_read_as_colcon_reads_it(tmp_path: Path, cache: Path):
    package = course_workspace(tmp_path) / 'src' / 'publisher_pkg'
    arguments = read_setup_py(package)
    assert arguments['name'] == 'publisher_pkg'
    assert arguments['data_files'][2] == ('share/publisher_pkg', ['launch/publisher_pkg_launch_file.launch.py'])
    assert find_source_packages(tmp_path / 'ros2_ws') == [package]
    found = source_package(package)
    assert found.executables == {'simple_publisher': 'publisher_pkg.simple_publisher:main'}
    # data_files put the launch file in share/publisher_pkg itself, not in a launch/ folder
    assert sorted(p.name for p in found.share.iterdir()) == ['package.xml', 'publisher_pkg_launch_file.launch.py']
    assert (found.prefix / 'share' / 'ament_index' / 'resource_index' / 'packages' / 'publisher_pkg').exists()
    assert found.share.is_relative_to(cache)
    # the tree follows the files: a new launch file appears, a removed one goes
    (package / 'launch' / 'second.launch.py').write_text(LAUNCH)
    assert (source_package(package).share / 'second.launch.py').read_text() == LAUNCH
    (package / 'launch' / 'second.launch.py').unlink()
    assert not (source_package(package).share / 'second.launch.py').exists()


def test_colcon_skips_build_folders_and_ignored_ones(tmp_path: Path):
    for folder in ('src/a', 'src/group/b', 'build/c', 'install/d', 'src/ignored/e', 'src/a/nested'):
        (tmp_path / folder).mkdir(parents=True)
        (tmp_path / folder / 'package.xml').write_text('<package><name>x</name></package>')
    (tmp_path / 'src' / 'ignored' / 'COLCON_IGNORE').touch()
    assert find_source_packages(tmp_path) == [tmp_path / 'src' / 'a', tmp_path / 'src' / 'group' / 'b']


def test_a_broken_setup_py_is_one_warning_line(tmp_path: Path, cache: Path):
    workspace = course_workspace(tmp_path)
    (workspace / 'src' / 'publisher_pkg' / 'setup.py').write_text('from setuptools import setup\nsetup(name=1/0)\n')
    env = dict(os.environ, ZROS_NODE_PATH=str(workspace))
    result = run_cli('run', 'publisher_pkg', 'simple_publisher', env=env)
    assert result.returncode != 0 and 'Traceback' not in result.stderr, result
    assert 'setup.py: ZeroDivisionError: division by zero' in result.stderr, result


# -- the course, run ---------------------------------------------------------------------------
def test_the_course_package_runs_from_its_workspace(domain: int, tmp_path: Path, cache: Path):
    """seed 001: `ros2 launch publisher_pkg publisher_pkg_launch_file.launch.py` after the
    workspace is made visible with `zros env` (colcon build's and source's role)."""
    workspace = course_workspace(tmp_path)
    paths = run_cli('env', workspace, '--json', timeout=30)
    assert paths.returncode == 0, paths
    import json
    env = dict(os.environ, ZROS_NODE_PATH=os.pathsep.join(json.loads(paths.stdout)['ZROS_NODE_PATH']))
    executables = run_cli('pkg', 'executables', 'publisher_pkg', env=env)
    assert executables.stdout == 'publisher_pkg simple_publisher\n', executables
    prefix = run_cli('pkg', 'prefix', 'publisher_pkg', env=env).stdout.strip()
    assert Path(prefix).is_relative_to(cache) and (Path(prefix) / 'share' / 'publisher_pkg').is_dir()
    zros = [sys.executable, '-m', 'zros']
    output = hears_the_publisher([*zros, 'launch', 'publisher_pkg', 'publisher_pkg_launch_file.launch.py'],
                                 env, tmp_path)
    assert '[simple_publisher-1]' in output and 'Publishing: "geometry_msgs.msg.Twist(' in output, output
    output = hears_the_publisher([*zros, 'run', 'publisher_pkg', 'simple_publisher'], env, tmp_path)
    assert '[simple_publisher]: Publishing:' in output, output


def test_the_course_package_runs_after_pip_install_editable(domain: int, tmp_path: Path, cache: Path,
                                                             fresh_venv: Path):
    package = course_workspace(tmp_path) / 'src' / 'publisher_pkg'
    installed = subprocess.run([fresh_venv, '-m', 'pip', 'install', '-q', '--no-deps',
                                '-e', package], capture_output=True, text=True, timeout=300)
    assert installed.returncode == 0, installed.stderr
    elsewhere = tmp_path / 'elsewhere'
    elsewhere.mkdir()
    env = dict(os.environ)
    output = hears_the_publisher([str(fresh_venv), '-m', 'zros', 'launch', 'publisher_pkg',
                                  'publisher_pkg_launch_file.launch.py'], env, elsewhere)
    assert 'Publishing:' in output, output


def test_an_install_prefix_is_read_through_its_ament_index(domain: int, tmp_path: Path):
    """A colcon install space (AMENT_PREFIX_PATH): share/<pkg> and the scripts of lib/<pkg>."""
    prefix = tmp_path / 'install' / 'publisher_pkg'
    (prefix / 'share' / 'ament_index' / 'resource_index' / 'packages').mkdir(parents=True)
    (prefix / 'share' / 'ament_index' / 'resource_index' / 'packages' / 'publisher_pkg').touch()
    (prefix / 'share' / 'publisher_pkg').mkdir()
    (prefix / 'share' / 'publisher_pkg' / 'publisher_pkg_launch_file.launch.py').write_text(LAUNCH)
    script = prefix / 'lib' / 'publisher_pkg' / 'simple_publisher'
    script.parent.mkdir(parents=True)
    script.write_text('#!/usr/bin/python3\n' + SIMPLE_PUBLISHER)
    script.chmod(0o755)
    env = dict(os.environ, AMENT_PREFIX_PATH=str(prefix))
    assert run_cli('pkg', 'prefix', 'publisher_pkg', env=env).stdout.strip() == str(prefix)
    output = hears_the_publisher([sys.executable, '-m', 'zros', 'launch', 'publisher_pkg',
                                  'publisher_pkg_launch_file.launch.py'], env, tmp_path)
    assert 'Publishing:' in output, output


# seed 000: the autonomous_exploration package, its launch file assembled from the course's fragments
EXPLORATION_LAUNCH = """import os

from ament_index_python.packages import get_package_share_directory
from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument
from launch.actions import IncludeLaunchDescription
from launch.launch_description_sources import PythonLaunchDescriptionSource
from launch.substitutions import LaunchConfiguration
from launch_ros.actions import Node

TURTLEBOT3_MODEL = os.environ['TURTLEBOT3_MODEL']


def generate_launch_description():
    use_sim_time = LaunchConfiguration('use_sim_time', default='True')
    x_pose = LaunchConfiguration('x_pose', default='-2.0')
    y_pose = LaunchConfiguration('y_pose', default='-0.5')
    param_file_name = TURTLEBOT3_MODEL + '.yaml'
    param_dir = os.path.join(
        get_package_share_directory('turtlebot3_navigation2'),
        'param',
        param_file_name)
    rviz_config_dir = os.path.join(
        get_package_share_directory('nav2_bringup'),
        'rviz',
        'nav2_default_view.rviz')
    turtlebot3_world_cmd = IncludeLaunchDescription(
        PythonLaunchDescriptionSource([os.path.join(
            get_package_share_directory('turtlebot3_gazebo'),
            'launch'),
            '/turtlebot3_world.launch.py']),
        launch_arguments={
            'use_sim_time': use_sim_time,
            'x_pose': x_pose,
            'y_pose': y_pose
        }.items()
    )
    navigation_cmd = IncludeLaunchDescription(
        PythonLaunchDescriptionSource([
            os.path.join(
                get_package_share_directory('nav2_bringup'),
                'launch'), '/bringup_launch.py']),
        launch_arguments={
            'map' : '~/.map.yaml',
            'use_sim_time': use_sim_time,
            'slam' : 'True',
            'params_file': param_dir}.items(),
    )
    rviz_cmd = Node(
        package='rviz2',
        executable='rviz2',
        name='rviz2',
        arguments=['-d', rviz_config_dir],
        parameters=[{'use_sim_time': use_sim_time}],
        output='screen')
    explore_lite_cmd = IncludeLaunchDescription(
        PythonLaunchDescriptionSource([os.path.join(
            get_package_share_directory('explore_lite'), 'launch'),
            '/explore.launch.py']),
        launch_arguments={
            'use_sim_time': use_sim_time}.items(),
    )
    ld = LaunchDescription()
    ld.add_action(turtlebot3_world_cmd)
    ld.add_action(navigation_cmd)
    ld.add_action(rviz_cmd)
    ld.add_action(explore_lite_cmd)
    return ld
"""


def test_the_exploration_course_package_launches_as_printed(tmp_path: Path, cache: Path):
    """seed 000: `ros2 pkg create --build-type ament_python autonomous_exploration`, the launch file,
    setup.py's `glob(os.path.join('launch', '*launch.[pxy][yma]*'))`, then `ros2 launch
    autonomous_exploration autonomous_exploration.launch.py x_pose:=0.5 y_pose:=2.0`."""
    src = tmp_path / 'turtlebot3_ws' / 'src'
    src.mkdir(parents=True)
    assert run_cli('pkg', 'create', '--build-type', 'ament_python', 'autonomous_exploration',
                   '--destination-directory', src).returncode == 0
    package = src / 'autonomous_exploration'
    (package / 'launch').mkdir()
    (package / 'launch' / 'autonomous_exploration.launch.py').write_text(EXPLORATION_LAUNCH)
    setup = (package / 'setup.py').read_text()
    setup = 'import os\nfrom glob import glob\n' + setup.replace(
        "('share/' + package_name, ['package.xml']),",
        "('share/' + package_name, ['package.xml']),\n"
        "        (os.path.join('share', package_name, 'launch'),\n"
        "         glob(os.path.join('launch', '*launch.[pxy][yma]*')))")
    (package / 'setup.py').write_text(setup)
    env = dict(os.environ, ZROS_NODE_PATH=str(src), TURTLEBOT3_MODEL='burger')
    plan = run_cli('launch', 'autonomous_exploration', 'autonomous_exploration.launch.py', 'x_pose:=0.5',
                   'y_pose:=2.0', '--print', '--log-dir', tmp_path / 'log', env=env, timeout=60)
    assert plan.returncode == 0, plan
    for process in ('gzserver', 'async_slam_toolbox_node', 'bt_navigator', 'rviz2', 'explore'):
        assert f'process [{process}-' in plan.stdout, (process, plan.stdout)


def test_the_repository_root_is_not_a_workspace():
    assert find_source_packages(REPO / 'nodes') == []


def test_a_fetched_cmake_package_keeps_zros_nodes_and_uses_its_own_files(tmp_path: Path, cache: Path):
    """slam_toolbox or turtlebot3_gazebo cloned into a workspace: their nodes are compiled, so
    zros's stand-ins of the same package run, with the clone's launch and config files."""
    package = tmp_path / 'ws' / 'src' / 'slam_toolbox'
    (package / 'config').mkdir(parents=True)
    (package / 'package.xml').write_text('<package format="3"><name>slam_toolbox</name>'
                                         '<export><build_type>ament_cmake</build_type></export></package>')
    (package / 'config' / 'mapper_params_online_async.yaml').write_text('slam_toolbox:\n  ros__parameters: {}\n')
    env = dict(os.environ, ZROS_NODE_PATH=str(tmp_path / 'ws'))
    share = run_cli('pkg', 'prefix', '--share', 'slam_toolbox', env=env).stdout.strip()
    assert share == str(package)
    executables = run_cli('pkg', 'executables', 'slam_toolbox', env=env).stdout
    assert 'slam_toolbox async_slam_toolbox_node' in executables, executables


def test_ament_resources_and_launch_condition_module():
    from zros.ament_index_python.resources import get_resource_types, has_resource
    from zros.launch import condition
    from zros.launch.conditions import Condition
    assert has_resource('packages', 'turtlebot3_gazebo') and not has_resource('packages', 'image_view')
    assert 'packages' in get_resource_types()
    assert condition.Condition is Condition
