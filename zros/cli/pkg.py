"""`zros pkg create|list|executables|prefix`: your own packages, as ros2 pkg finds them.

A package is a folder (see docs/packages.md): `zros pkg create` writes one that runs at once
(an installable project with a node, its launch file, interface folders and a test), and the
other verbs read the package index, zros.ament_index_python.packages.
"""
from __future__ import annotations

import argparse
import json
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from zros.ament_index_python.executables import Executables

__all__ = ['add_arguments']


def add_arguments(parser: argparse.ArgumentParser) -> None:
    sub = parser.add_subparsers(dest='pkg_verb', metavar='<command>')
    p = sub.add_parser('create', help='Create a new package (no build step: pip install -e it, or put it on '
                                      'ZROS_NODE_PATH)')
    p.add_argument('package_name', help='The package name, e.g. my_pkg')
    p.add_argument('--node-name', help='Name of an empty node to create (and its entry point)')
    p.add_argument('--dependencies', nargs='+', default=[], metavar='PKG',
                   help='ROS packages the node uses (interfaces such as std_msgs); listed in README.md')
    p.add_argument('--destination-directory', default='.', help='Where to create the package folder')
    p.add_argument('--description', default='TODO: Package description')
    p.add_argument('--license', default='TODO: License declaration')
    p.add_argument('--maintainer-name', default=None)
    p.add_argument('--maintainer-email', default=None)
    p.add_argument('--build-type', default=None, choices=('ament_python', 'ament_cmake', 'cmake'),
                   help="the ROS layout (package.xml, setup.py or CMakeLists.txt) as ros2 pkg create writes "
                        "it; without it, a zros Python project (pyproject.toml)")
    p.set_defaults(handler=cmd_create)
    p = sub.add_parser('list', help='Output a list of available packages')
    p.add_argument('--json', action='store_true', help='Machine-readable output')
    p.set_defaults(handler=cmd_list)
    p = sub.add_parser('executables', help='Output a list of package specific executables')
    p.add_argument('package_name', nargs='?', help='The package name (all packages when omitted)')
    p.add_argument('--full-path', action='store_true', help='Print the file (or entry point) of each executable')
    p.add_argument('--json', action='store_true', help='Machine-readable output')
    p.set_defaults(handler=cmd_executables)
    p = sub.add_parser('prefix', help='Output the prefix path of a package')
    p.add_argument('package_name', help='The package name')
    p.add_argument('--share', action='store_true', help='Show the share directory of the package')
    p.set_defaults(handler=cmd_prefix)


def _packages(index: Executables | None = None) -> list[str]:
    """Every package: those of the package index and those with executables."""
    from zros.ament_index_python.executables import Executables
    from zros.ament_index_python.packages import package_directories
    return sorted(set(package_directories()) | set((index or Executables()).packages()))


def cmd_list(args: argparse.Namespace) -> int:
    packages = _packages()
    print(json.dumps(packages) if args.json else '\n'.join(packages))
    return 0


def cmd_executables(args: argparse.Namespace) -> int:
    from zros.ament_index_python.executables import Executables
    from zros.errors import CliError, with_suggestion
    index = Executables()
    known = _packages(index)
    if args.package_name is not None and args.package_name not in known:
        raise CliError(with_suggestion(f"Package '{args.package_name}' not found", args.package_name, known))
    packages = [args.package_name] if args.package_name else known
    rows = [(package, executable) for package in packages for executable in index.of(package)]
    if args.full_path:
        rows = [(package, _where(package, executable)) for package, executable in rows]
    if args.json:
        print(json.dumps([{'package': package, 'executable': executable} for package, executable in rows]))
    else:
        for package, executable in rows:
            print(executable if args.full_path else f'{package} {executable}')
    return 0


def _where(package: str, executable: str) -> str:
    """The file of an executable, or its entry point (`module:function`)."""
    from importlib import metadata
    from zros.ament_index_python.packages import package_directories
    for ep in metadata.entry_points(group='zros.nodes'):
        if ep.name == f'{package}/{executable}':
            return ep.value
    return str(package_directories()[package] / f'{executable}.py')


def cmd_prefix(args: argparse.Namespace) -> int:
    from zros.ament_index_python.packages import PackageNotFoundError, get_package_prefix, get_package_share_directory
    from zros.errors import CliError
    try:
        print(get_package_share_directory(args.package_name) if args.share else get_package_prefix(args.package_name))
    except PackageNotFoundError:
        raise CliError('Package not found') from None
    return 0


def cmd_create(args: argparse.Namespace) -> int:
    from zros.cli.pkg_create import create_package
    return create_package(args)
