"""`zros interface list|packages|package|show|proto`."""
from __future__ import annotations

import argparse

__all__ = ['add_arguments', 'expanded_definition']


def add_arguments(parser: argparse.ArgumentParser) -> None:
    sub = parser.add_subparsers(dest='interface_verb', metavar='<command>')
    p = sub.add_parser('list', help='List all interface types available')
    p.add_argument('-m', '--only-msgs', action='store_true', help='Print out only the message types')
    p.add_argument('-s', '--only-srvs', action='store_true', help='Print out only the service types')
    p.add_argument('-a', '--only-actions', action='store_true', help='Print out only the action types')
    p.add_argument('--json', action='store_true', help='Machine-readable output')
    p.set_defaults(handler=cmd_list)
    p = sub.add_parser('packages', help='Output a list of packages that provide interfaces')
    p.add_argument('-m', '--only-msgs', action='store_true')
    p.add_argument('-s', '--only-srvs', action='store_true')
    p.add_argument('-a', '--only-actions', action='store_true')
    p.add_argument('--json', action='store_true', help='Machine-readable output')
    p.set_defaults(handler=cmd_packages)
    p = sub.add_parser('package', help='Output a list of available interface types within one package')
    p.add_argument('package_name')
    p.add_argument('--json', action='store_true', help='Machine-readable output')
    p.set_defaults(handler=cmd_package)
    p = sub.add_parser('show', help='Output the interface definition')
    p.add_argument('type', help="e.g. 'geometry_msgs/msg/Twist'")
    p.add_argument('--no-comments', action='store_true', help='Strip comments from the output')
    p.add_argument('--all-comments', action='store_true', help='Show the comments of nested types too')
    p.set_defaults(handler=cmd_show)
    p = sub.add_parser('proto', help='Output an interface prototype (YAML)')
    p.add_argument('type')
    p.add_argument('--no-quotes', action='store_true', help='Do not wrap the prototype in single quotes')
    p.set_defaults(handler=cmd_proto)


def _kinds(args: argparse.Namespace) -> tuple[str, ...]:
    picked = tuple(k for k, on in (('msg', args.only_msgs), ('srv', args.only_srvs),
                                    ('action', args.only_actions)) if on)
    return picked or ('msg', 'srv', 'action')


def cmd_list(args: argparse.Namespace) -> int:
    from zros.typesupport import list_interfaces
    titles = {'msg': 'Messages', 'srv': 'Services', 'action': 'Actions'}
    if args.json:
        import json
        print(json.dumps({titles[k].lower(): list_interfaces(kinds=(k,)) for k in _kinds(args)}))
        return 0
    for kind in _kinds(args):
        print(f'{titles[kind]}:')
        for name in list_interfaces(kinds=(kind,)):
            print(f'    {name}')
    return 0


def cmd_packages(args: argparse.Namespace) -> int:
    from zros.typesupport import list_interfaces
    packages = sorted({n.split('/')[0] for n in list_interfaces(kinds=_kinds(args))})
    if args.json:
        import json
        print(json.dumps(packages))
        return 0
    for package in packages:
        print(package)
    return 0


def cmd_package(args: argparse.Namespace) -> int:
    from zros.errors import CliError
    from zros.typesupport import list_interfaces, list_packages
    if args.package_name not in list_packages():
        raise CliError(f"Unknown package '{args.package_name}'")
    names = list_interfaces(args.package_name)
    if args.json:
        import json
        print(json.dumps(names))
        return 0
    for name in names:
        print(name)
    return 0


def _nested_type_of(line: str, spec) -> str | None:
    """The nested message type that a definition line declares a field of, or None."""
    from zros.idl import strip_comment
    parts = strip_comment(line).split()
    if len(parts) < 2:
        return None
    name = parts[1].split('=')[0]
    for field in spec.fields:
        if field.name == name and not field.type.is_primitive:
            return field.type.base
    return None


def _render(spec, indent: str, comments: bool, nested_comments: bool) -> list[str]:
    from zros.idl import strip_comment
    from zros.typesupport import get_message
    out = []
    for line in spec.text.splitlines():
        shown = line if comments else strip_comment(line).rstrip()
        if not comments and not shown.strip():
            continue
        out.append(indent + shown)
        nested = _nested_type_of(line, spec)
        if nested:
            out.extend(_render(get_message(nested)._SPEC, indent + '\t', nested_comments, nested_comments))
    return out


def expanded_definition(type_name: str, *, comments: bool = True, nested_comments: bool = False) -> str:
    """The definition text with each nested type's definition indented under its field, as
    `ros2 interface show` prints it (nested comments only with --all-comments)."""
    from zros.typesupport import get_type
    cls = get_type(type_name)
    if hasattr(cls, 'Request'):
        parts = [cls.Request._SPEC, cls.Response._SPEC]
    elif hasattr(cls, 'Goal'):
        parts = [cls.Goal._SPEC, cls.Result._SPEC, cls.Feedback._SPEC]
    else:
        parts = [cls._SPEC]
    blocks = ['\n'.join(_render(spec, '', comments, nested_comments and comments)).rstrip('\n')
              for spec in parts]
    return '\n---\n'.join(blocks)


def cmd_show(args: argparse.Namespace) -> int:
    print(expanded_definition(args.type, comments=not args.no_comments, nested_comments=args.all_comments))
    return 0


def cmd_proto(args: argparse.Namespace) -> int:
    from zros.errors import CliError
    from zros.convert import yaml_prototype
    from zros.typesupport import get_type
    cls = get_type(args.type)
    if hasattr(cls, 'Request'):
        cls = cls.Request
    elif hasattr(cls, 'Goal'):
        cls = cls.Goal
    elif not hasattr(cls, '_ENC'):
        raise CliError(f"'{args.type}' is not an interface type")
    text = yaml_prototype(cls).rstrip('\n')
    print(text if args.no_quotes else f'"{text}"')
    return 0
