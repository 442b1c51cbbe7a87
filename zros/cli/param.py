"""`zros param list|get|set|describe|dump|load|delete` with ros2 param's messages."""
from __future__ import annotations

import argparse
import re
import sys

from zros.cli.common import absolute_node_name, cli_context, cli_node, graph_entities
from zros.graph import EntityKind
from zros.graph_content import is_hidden

__all__ = ['add_arguments']

_TYPE_NAMES = {1: 'bool', 2: 'integer', 3: 'double', 4: 'string', 5: 'byte array', 6: 'boolean array',
               7: 'integer array', 8: 'double array', 9: 'string array'}


def add_arguments(parser: argparse.ArgumentParser) -> None:
    sub = parser.add_subparsers(dest='param_verb', metavar='<command>')

    def common(p: argparse.ArgumentParser) -> None:
        p.add_argument('--timeout', type=float, default=5.0, help='Seconds to wait for the node (default 5)')
        p.add_argument('--include-hidden-nodes', action='store_true')

    p = sub.add_parser('list', help='Output a list of available parameters')
    p.add_argument('node_name', nargs='?', help='Node name (all nodes when omitted)')
    p.add_argument('--filter', help='Only list parameters whose names match this regular expression')
    p.add_argument('--param-type', action='store_true', help='Print the type of each parameter')
    common(p)
    p.set_defaults(handler=cmd_list)
    p = sub.add_parser('get', help='Get a parameter')
    p.add_argument('node_name')
    p.add_argument('parameter_name')
    p.add_argument('--hide-type', action='store_true', help='Hide the type information')
    common(p)
    p.set_defaults(handler=cmd_get)
    p = sub.add_parser('set', help='Set a parameter')
    p.add_argument('node_name')
    p.add_argument('parameter_name')
    p.add_argument('value', help='Value in YAML (42, 1.5, true, hello, "[1, 2]")')
    common(p)
    p.set_defaults(handler=cmd_set)
    p = sub.add_parser('describe', help='Show descriptive information about declared parameters')
    p.add_argument('node_name')
    p.add_argument('parameter_names', nargs='+')
    common(p)
    p.set_defaults(handler=cmd_describe)
    p = sub.add_parser('dump', help='Dump the parameters of a node as YAML (ROS 2 parameter file layout)')
    p.add_argument('node_name')
    p.add_argument('--output-dir', help='Write <node>.yaml into this directory instead of printing')
    p.add_argument('--print', action='store_true',
                   help='Print the YAML (the default; with --output-dir, print it as well as writing it)')
    common(p)
    p.set_defaults(handler=cmd_dump)
    p = sub.add_parser('load', help='Load parameters of a node from a YAML file')
    p.add_argument('node_name')
    p.add_argument('parameter_file')
    p.add_argument('--no-use-wildcard', action='store_true', help="Ignore '/**' entries of the file")
    common(p)
    p.set_defaults(handler=cmd_load)
    p = sub.add_parser('delete', help='Delete (undeclare) a parameter')
    p.add_argument('node_name')
    p.add_argument('parameter_name')
    common(p)
    p.set_defaults(handler=cmd_delete)


class _Remote:
    """Calls one node's parameter services."""

    def __init__(self, ctx, node_name: str, timeout: float) -> None:
        from zros.errors import CliError
        self.fq = absolute_node_name(node_name)
        self.timeout = timeout
        if not any(e.kind == EntityKind.NODE and e.node_fqn == self.fq for e in graph_entities(ctx)):
            raise CliError(f"Node not found: '{self.fq}'")
        self.node = cli_node(ctx)
        self._clients = {}

    def call(self, service: str, srv_name: str, **fields):
        from zros.errors import CliError
        from zros.typesupport import get_service
        srv_type = get_service(f'rcl_interfaces/srv/{srv_name}')
        client = self._clients.get(service)
        if client is None:
            client = self._clients[service] = self.node.create_client(srv_type, f'{self.fq}/{service}')
        if not client.wait_for_service(self.timeout):
            raise CliError(f"Node '{self.fq}' does not serve parameters ({service} not available)")
        response = client.call(srv_type.Request(**fields), timeout_sec=self.timeout)
        if response is None:
            raise CliError(f"Node '{self.fq}' did not answer {service} within {self.timeout:g} s")
        return response

    def list_names(self) -> list[str]:
        return list(self.call('list_parameters', 'ListParameters').result.names)

    def get_values(self, names: list[str]) -> list:
        return list(self.call('get_parameters', 'GetParameters', names=names).values)


def _value_text(value) -> str:
    """ros2 param get's sentence for a ParameterValue."""
    from zros.parameter import parameter_value_to_python
    kind = value.type
    py = parameter_value_to_python(value)
    if kind == 0:
        return 'Parameter not set.'
    label = {1: 'Boolean value is:', 2: 'Integer value is:', 3: 'Double value is:', 4: 'String value is:',
             5: 'Byte values are:', 6: 'Boolean values are:', 7: 'Integer values are:',
             8: 'Double values are:', 9: 'String values are:'}[kind]
    return f'{label} {py}'


def cmd_list(args: argparse.Namespace) -> int:
    from zros.parameter_service import PARAMETER_SERVICES
    with cli_context() as ctx:
        entities = graph_entities(ctx)
        if args.node_name:
            nodes = [absolute_node_name(args.node_name)]
        else:
            nodes = sorted({e.node_fqn for e in entities if e.kind == EntityKind.SERVICE
                            and e.name == f'{e.node_fqn}/{PARAMETER_SERVICES[3]}'
                            and (args.include_hidden_nodes or not is_hidden(e.node_fqn))})
        pattern = re.compile(args.filter) if args.filter else None
        for fq in nodes:
            remote = _Remote(ctx, fq, args.timeout)
            names = sorted(n for n in remote.list_names() if pattern is None or pattern.search(n))
            print(f'{fq}:')
            if args.param_type and names:
                types = remote.call('get_parameter_types', 'GetParameterTypes', names=names).types
                for name, kind in zip(names, types):
                    print(f'  {name} (type: {_TYPE_NAMES.get(int(kind), "not set")})')
            else:
                for name in names:
                    print(f'  {name}')
    return 0


def cmd_get(args: argparse.Namespace) -> int:
    from zros.errors import CliError
    from zros.parameter import parameter_value_to_python
    with cli_context() as ctx:
        remote = _Remote(ctx, args.node_name, args.timeout)
        values = remote.get_values([args.parameter_name])
    if not values or values[0].type == 0:   # undeclared, or declared with no value yet
        raise CliError('Parameter not set.')
    value = values[0]
    print(parameter_value_to_python(value) if args.hide_type else _value_text(value))
    return 0


# ROS parameter names: tokens of letters, digits and '_' joined by '.' (nesting) or '/' (as in
# qos_overrides./topic.publisher.depth), not starting with a digit.
_PARAMETER_NAME = re.compile(r'^[A-Za-z_][A-Za-z0-9_]*(?:[./]+[A-Za-z0-9_]+)*$')


def _parameter_msg(name: str, value):
    from zros.errors import CliError
    if not _PARAMETER_NAME.match(name):
        raise CliError(f"invalid parameter name '{name}': use letters, digits and '_', with '.' between "
                       'nested names')
    from zros.parameter import Parameter
    try:
        return Parameter(name, value=value).to_parameter_msg()
    except TypeError as exc:
        from zros.errors import CliError
        raise CliError(f"invalid value for '{name}': {exc}") from None


def cmd_set(args: argparse.Namespace) -> int:
    from zros.errors import CliError
    from zros.parameter import parse_parameter_value
    msg = _parameter_msg(args.parameter_name, parse_parameter_value(args.value))
    with cli_context() as ctx:
        remote = _Remote(ctx, args.node_name, args.timeout)
        result = remote.call('set_parameters', 'SetParameters', parameters=[msg]).results[0]
    if result.successful:
        print('Set parameter successful')
        return 0
    raise CliError(f'Setting parameter failed: {result.reason}' if result.reason else 'Setting parameter failed')


def cmd_describe(args: argparse.Namespace) -> int:
    with cli_context() as ctx:
        remote = _Remote(ctx, args.node_name, args.timeout)
        descriptors = remote.call('describe_parameters', 'DescribeParameters', names=args.parameter_names).descriptors
    for descriptor in descriptors:
        print(f'Parameter name: {descriptor.name}')
        print(f'  Type: {_TYPE_NAMES.get(int(descriptor.type), "not set")}')
        if descriptor.description:
            print(f'  Description: {descriptor.description}')
        constraints = []
        if descriptor.read_only:
            constraints.append('    Read only: true')
        for rng in list(descriptor.integer_range) + list(descriptor.floating_point_range):
            constraints += [f'    Min value: {rng.from_value}', f'    Max value: {rng.to_value}']
            if rng.step:
                constraints.append(f'    Step: {rng.step}')
        if descriptor.additional_constraints:
            constraints.append(f'    {descriptor.additional_constraints}')
        if descriptor.dynamic_typing:
            constraints.append('    Dynamic typing: true')
        if constraints:
            print('  Constraints:')
            print('\n'.join(constraints))
    return 0


def _nest(flat: dict) -> dict:
    tree: dict = {}
    for name, value in flat.items():
        node = tree
        parts = name.split('.')
        for part in parts[:-1]:
            node = node.setdefault(part, {})
        node[parts[-1]] = value
    return tree


def cmd_dump(args: argparse.Namespace) -> int:
    import os

    import yaml

    from zros.parameter import parameter_value_to_python
    with cli_context() as ctx:
        remote = _Remote(ctx, args.node_name, args.timeout)
        names = sorted(remote.list_names())
        values = remote.get_values(names) if names else []
        if len(values) != len(names):   # a parameter with no value yet empties the answer: ask one by one
            pairs = [(name, value) for name in names for value in remote.get_values([name])]
            names, values = [name for name, _ in pairs], [value for _, value in pairs]
    flat = {}
    for name, value in zip(names, values):
        py = parameter_value_to_python(value)
        if isinstance(py, list) and py and isinstance(py[0], bytes):
            py = [b[0] for b in py]
        flat[name] = py
    text = yaml.safe_dump({remote.fq: {'ros__parameters': _nest(flat)}}, default_flow_style=False, sort_keys=True)
    if args.output_dir:
        path = os.path.join(args.output_dir, remote.fq.strip('/').replace('/', '__') + '.yaml')
        with open(path, 'w', encoding='utf-8') as stream:
            stream.write(text)
        print(f'Saving to:  {path}')
    if args.print or not args.output_dir:
        sys.stdout.write(text)
    return 0


def cmd_load(args: argparse.Namespace) -> int:
    from zros.errors import CliError
    from zros.parameter import load_parameter_file
    fq = absolute_node_name(args.node_name)
    values = load_parameter_file(args.parameter_file, fq, use_wildcard=not args.no_use_wildcard)
    if not values:
        raise CliError(f"'{args.parameter_file}' has no parameters for node '{fq}'")
    failed = False
    with cli_context() as ctx:
        remote = _Remote(ctx, fq, args.timeout)
        # A dump holds read-only parameters too (every node's start_type_description_service):
        # loading it back skips them rather than failing on them.
        described = remote.call('describe_parameters', 'DescribeParameters', names=list(values)).descriptors
        read_only = {d.name for d in described if d.read_only}
        for name, value in values.items():
            if name in read_only:
                print(f'Skipped read-only parameter {name}')
                continue
            result = remote.call('set_parameters', 'SetParameters', parameters=[_parameter_msg(name, value)]).results[0]
            if result.successful:
                print(f'Set parameter {name} successful')
            else:
                failed = True
                print(f'Set parameter {name} failed' + (f': {result.reason}' if result.reason else ''))
    return 1 if failed else 0


def cmd_delete(args: argparse.Namespace) -> int:
    from interfaces.rcl_interfaces.msg import Parameter as ParameterMsg
    from zros.errors import CliError
    with cli_context() as ctx:
        remote = _Remote(ctx, args.node_name, args.timeout)
        result = remote.call('set_parameters', 'SetParameters',
                             parameters=[ParameterMsg(name=args.parameter_name)]).results[0]
    if result.successful:
        print('Deleted parameter successfully')
        return 0
    raise CliError(f'Deleting parameter failed: {result.reason}' if result.reason else 'Deleting parameter failed')
