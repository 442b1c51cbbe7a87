"""`zros pkg create --build-type ament_python|ament_cmake`: the package as `ros2 pkg create`
lays it out, for a course that edits its setup.py and package.xml.

zros reads these files where they are (zros.ament_index_python.ros_packages): put the workspace
on ZROS_NODE_PATH (`eval "$(zros env ~/ros2_ws)"`) or `pip install -e` the package, and
`zros run` / `zros launch` find its console scripts and data files with no `colcon build`.

    my_pkg/                      (ament_python)
      package.xml                <build_type>ament_python</build_type>, one <depend> per dependency
      setup.py                   data_files (ament index marker, package.xml), console_scripts
      setup.cfg                  scripts into lib/my_pkg, as ros2 run expects them
      resource/my_pkg            the ament index marker
      my_pkg/__init__.py
      my_pkg/my_node.py          with --node-name
      test/                      for the package's pytest tests

    my_pkg/                      (ament_cmake: interfaces, or code zros does not build)
      package.xml, CMakeLists.txt, include/my_pkg/, src/
"""
from __future__ import annotations

from pathlib import Path
from string import Template

__all__ = ['ros_layout']

PACKAGE_XML = '''<?xml version="1.0"?>
<?xml-model href="http://download.ros.org/schema/package_format3.xsd" schematypens="http://www.w3.org/2001/XMLSchema"?>
<package format="3">
  <name>${package}</name>
  <version>0.0.0</version>
  <description>${description}</description>
  <maintainer email="${email}">${maintainer}</maintainer>
  <license>${license}</license>
${buildtool}${depends}  <export>
    <build_type>${build_type}</build_type>
  </export>
</package>
'''

SETUP_PY = '''from setuptools import find_packages, setup

package_name = '${package}'

setup(
    name=package_name,
    version='0.0.0',
    packages=find_packages(exclude=['test']),
    data_files=[
        ('share/ament_index/resource_index/packages', ['resource/' + package_name]),
        ('share/' + package_name, ['package.xml']),
    ],
    install_requires=['setuptools'],
    zip_safe=True,
    maintainer='${maintainer}',
    maintainer_email='${email}',
    description='${description}',
    license='${license}',
    tests_require=['pytest'],
    entry_points={
        'console_scripts': [${console_scripts}
        ],
    },
)
'''

SETUP_CFG = '''[develop]
script_dir=$$base/lib/${package}
[install]
install_scripts=$$base/lib/${package}
'''

NODE = '''def main():
    print('Hi from ${package}.')


if __name__ == '__main__':
    main()
'''

CMAKELISTS = '''cmake_minimum_required(VERSION 3.8)
project(${package})

find_package(ament_cmake REQUIRED)
${find_packages}
ament_package()
'''


def ros_layout(fields: dict[str, str], build_type: str, node: str | None,
               dependencies: list[str]) -> dict[str, str]:
    """{relative path: text} of a package as `ros2 pkg create --build-type BUILD_TYPE` writes it."""
    package = fields['package']
    values = dict(fields, build_type=build_type,
                  depends=''.join(f'  <depend>{d}</depend>\n' for d in dependencies),
                  buildtool='  <buildtool_depend>ament_cmake</buildtool_depend>\n' if build_type == 'ament_cmake' else '',
                  console_scripts=f"\n            '{node} = {package}.{node}:main'," if node else '',
                  find_packages=''.join(f'find_package({d} REQUIRED)\n' for d in dependencies))
    if build_type == 'ament_cmake':
        templates = {'package.xml': PACKAGE_XML, 'CMakeLists.txt': CMAKELISTS,
                     f'include/{package}/.gitkeep': '', 'src/.gitkeep': ''}
    else:
        templates = {'package.xml': PACKAGE_XML, 'setup.py': SETUP_PY, 'setup.cfg': SETUP_CFG,
                     f'resource/{package}': '', f'{package}/__init__.py': '', 'test/.gitkeep': ''}
        if node:
            templates[f'{package}/{node}.py'] = NODE
    return {path: Template(text).substitute(values) for path, text in templates.items()}


def next_steps(root: Path) -> str:
    """What to do instead of `colcon build` and `source install/setup.bash`."""
    root = root.resolve()
    workspace = root.parent.parent if root.parent.name == 'src' else root.parent
    return (f'\nnext: no colcon build; either  eval "$(zros env {workspace})"  '
            f'or  pip install -e {root}')
