"""`zros pkg create`: a package a student can run at once, with no build step.

With `--build-type ament_python` (or `ament_cmake`) it writes ROS's own layout
(zros.cli.pkg_create_ros). Without it, it writes an installable Python project (`pip install -e my_pkg`) that is also usable in place
(its folder on ZROS_NODE_PATH):

    my_pkg/
      pyproject.toml          entry points: zros.nodes (my_pkg/my_node), zros.packages (my_pkg)
      README.md
      my_pkg/               the Python package = the share directory
        __init__.py
        my_node.py            a node (with --node-name)
        launch/my_pkg.launch.py
        msg/ srv/ action/     the package's interfaces: `from interfaces.my_pkg.msg import X`
      tests/test_my_node.py   a working test (zros.testing fixtures)

Output follows `ros2 pkg create`'s.
"""
from __future__ import annotations

import argparse
import getpass
import re
from pathlib import Path
from string import Template

__all__ = ['create_package']

_NAME = re.compile(r'[a-z][a-z0-9_]*')

PYPROJECT = '''\
[build-system]
requires = ["setuptools>=64"]
build-backend = "setuptools.build_meta"

[project]
name = "${package}"
version = "0.0.0"
description = "${description}"
license = { text = "${license}" }
authors = [{ name = "${maintainer}", email = "${email}" }]
requires-python = ">=3.11"
# zros itself (installed from its repository) is all a zros package needs; the ROS packages it
# uses (${dependencies}) ship with zros.
dependencies = []

[project.optional-dependencies]
test = ["pytest>=7.4"]

# `zros launch ${package} ...`, $$(find-pkg-share ${package}) and interfaces.${package}: the folder
# of the Python package ${package} is this package's share directory.
[project.entry-points."zros.packages"]
${package} = "${package}"
${entry_points}
[tool.setuptools]
packages = ["${package}"]

[tool.setuptools.package-data]
${package} = ["msg/*.msg", "srv/*.srv", "action/*.action", "launch/*", "param/*", "config/*", "map/*",
           "urdf/*", "rviz/*", "worlds/*"]

[tool.pytest.ini_options]
testpaths = ["tests"]
'''

ENTRY_POINTS = '''
# `zros run ${package} ${node}` calls ${package}.${node}:main
[project.entry-points."zros.nodes"]
"${package}/${node}" = "${package}.${node}:main"
'''

INIT = '''"""${package}: ${description}"""
'''

NODE = '''"""${node}: publishes a greeting on /chatter once a second (replace with your node's job).

Run it with `zros run ${package} ${node}`, or all of the package with
`zros launch ${package} ${package}.launch.py`.
"""
import sys

import zros
from zros.executors import ExternalShutdownException
from zros.node import Node

from interfaces.std_msgs.msg import String


class ${cls}(Node):

    def __init__(self):
        super().__init__('${node}')
        self.declare_parameter('greeting', 'Hello from ${package}')
        self.count = 0
        self.publisher = self.create_publisher(String, 'chatter', 10)
        self.timer = self.create_timer(1.0, self.on_timer)

    def on_timer(self):
        self.count += 1
        msg = String(data=f"{self.get_parameter('greeting').value}: {self.count}")
        self.get_logger().info(f'Publishing: {msg.data!r}')
        self.publisher.publish(msg)


def main(args=None):
    try:
        with zros.init(args=args):
            zros.spin(${cls}())
    except (KeyboardInterrupt, ExternalShutdownException):
        pass


if __name__ == '__main__':
    main(sys.argv)
'''

LAUNCH = '''"""Starts ${package}'s nodes: `zros launch ${package} ${package}.launch.py [greeting:=...]`."""
from zros.launch import LaunchDescription
from zros.launch.actions import DeclareLaunchArgument
from zros.launch.substitutions import LaunchConfiguration
from zros.launch_ros.actions import Node


def generate_launch_description():
    return LaunchDescription([
        DeclareLaunchArgument('greeting', default_value='Hello from the launch file'),${nodes}
    ])
'''

LAUNCH_NODE = '''
        Node(package='${package}', executable='${node}', output='screen',
             parameters=[{'greeting': LaunchConfiguration('greeting')}]),'''

TEST = '''"""Tests of ${node}: as a process (as `zros run ${package} ${node}` starts it) and in-process.

`zros_processes`, `zros_node` and `zros_context` come from zros.testing's pytest plugin: each test
runs in a zros domain of its own, and whatever it starts is stopped after it.
"""
from interfaces.std_msgs.msg import String
from zros.executors import SingleThreadedExecutor
from zros.testing import spin_until, wait_for_message

from ${package}.${node} import ${cls}


def test_${node}_publishes_when_run(zros_processes, zros_node):
    zros_processes.run('${package}', '${node}', '--ros-args', '-p', 'greeting:=Hi')
    listener = zros_node('test_listener')
    message = wait_for_message(listener, String, '/chatter', timeout=20.0)
    assert message.data.startswith('Hi: ')


def test_${node}_in_process(zros_context, zros_node):
    node = ${cls}()
    received = []
    listener = zros_node('test_listener')
    listener.create_subscription(String, '/chatter', received.append, 10)
    executor = SingleThreadedExecutor()
    executor.add_node(node)
    executor.add_node(listener)
    spin_until(executor, lambda: received, timeout=10.0, message='a greeting')
    assert received[0].data == 'Hello from ${package}: 1'
    node.destroy_node()
'''

EMPTY_TEST = '''"""The package's tests; zros.testing's fixtures (zros_processes, zros_node, zros_context) are at hand."""


def test_the_package_is_found(zros_context):
    from zros.ament_index_python.packages import get_package_share_path
    assert (get_package_share_path('${package}') / 'launch').is_dir()
'''

README = '''# ${package}

${description}

A zros package (no build step). Install it once, in the environment where zros is installed:

    pip install -e .            # from this folder; or put this folder on ZROS_NODE_PATH instead

Then:

    zros run ${package} ${node_or_exe}
    zros launch ${package} ${package}.launch.py
    zros pkg executables ${package}
    python -m pytest            # the tests in tests/

- Nodes are modules of `${package}/` with a `main()`, listed under `[project.entry-points."zros.nodes"]`
  in pyproject.toml (`"${package}/NAME" = "${package}.NAME:main"`); reinstall after adding one.
- Interfaces go in `${package}/msg/*.msg`, `${package}/srv/*.srv`, `${package}/action/*.action` and
  import as `from interfaces.${package}.msg import Name`: no build, just save the file.
- Launch files go in `${package}/launch/`, parameter files in `${package}/param/`.

Depends on: ${dependencies}.
'''


def _class_name(node: str) -> str:
    return ''.join(part.capitalize() for part in node.split('_')) or 'MyNode'


def _write(root: Path, files: dict[str, str]) -> None:
    print(f'creating folder {root}')
    for relative, text in files.items():
        path = root / relative
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)
        print(f'creating {path}')


def create_package(args: argparse.Namespace) -> int:
    from zros.errors import CliError
    package = args.package_name
    if not _NAME.fullmatch(package):
        raise CliError(f"package name '{package}' must start with a lowercase letter and hold only "
                       'lowercase letters, digits and underscores')
    node = args.node_name
    if node is not None and not _NAME.fullmatch(node):
        raise CliError(f"node name '{node}' must start with a lowercase letter and hold only lowercase "
                       'letters, digits and underscores')
    root = Path(args.destination_directory) / package
    if root.exists():
        raise CliError(f'Aborted: a folder named {package} already exists in {args.destination_directory}')
    maintainer = args.maintainer_name or getpass.getuser()
    email = args.maintainer_email or f'{maintainer}@todo.todo'
    dependencies = list(dict.fromkeys(['std_msgs', *args.dependencies])) if node else list(args.dependencies)
    build_type = {'cmake': 'ament_cmake'}.get(args.build_type, args.build_type)
    print('going to create a new package')
    for label, value in (('package name', package), ('destination directory', str(Path(args.destination_directory).resolve())),
                         ('version', '0.0.0'), ('description', args.description),
                         ('maintainer', [f'{maintainer} <{email}>']), ('licenses', [args.license]),
                         ('build type', build_type or 'ament_python'), ('dependencies', dependencies)):
        print(f'{label}: {value}')
    if node:
        print(f'node_name: {node}')
    fields = dict(package=package, description=args.description, license=args.license, maintainer=maintainer,
                  email=email, node=node or '', cls=_class_name(node or ''),
                  dependencies=', '.join(dependencies) or 'none', node_or_exe=node or 'EXECUTABLE')
    fields['entry_points'] = Template(ENTRY_POINTS).substitute(fields) if node else ''
    fields['nodes'] = Template(LAUNCH_NODE).substitute(fields) if node else ''
    if build_type is not None:
        from zros.cli.pkg_create_ros import next_steps, ros_layout
        _write(root, ros_layout(fields, build_type, node, list(args.dependencies)))
        print(next_steps(root))
        return 0
    files = {
        'pyproject.toml': PYPROJECT,
        'README.md': README,
        f'{package}/__init__.py': INIT,
        f'{package}/launch/{package}.launch.py': LAUNCH,
        f'{package}/msg/.gitkeep': '',
        f'{package}/srv/.gitkeep': '',
        f'{package}/action/.gitkeep': '',
    }
    if node:
        files[f'{package}/{node}.py'] = NODE
        files[f'tests/test_{node}.py'] = TEST
    else:
        files['tests/test_package.py'] = EMPTY_TEST
    _write(root, {relative: Template(template).substitute(fields) for relative, template in files.items()})
    print(f'\nnext: pip install -e {root}   (or: export ZROS_NODE_PATH={root.resolve()})')
    return 0
