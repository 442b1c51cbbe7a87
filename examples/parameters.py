"""Declare parameters, validate changes to them, and use them in a timer.

    python examples/parameters.py                                  # says 'Hello' every second
    python examples/parameters.py --ros-args -p greeting:=Hi -p period:=0.5
    python examples/parameters.py --once                           # print the parameters and exit

While it runs: `zros param set /parameters_example greeting Bonjour` changes what it says, and
`zros param set /parameters_example period -1.0` is refused by the callback below.
"""
from __future__ import annotations

import argparse

import zros
from zros.node import Node
from zros.parameter import Parameter

from interfaces.rcl_interfaces.msg import ParameterDescriptor, SetParametersResult

from common import parse_args, run


def refuse_bad_period(parameters: list[Parameter]) -> SetParametersResult:
    """Reject a period that is not positive; every other change is accepted."""
    for parameter in parameters:
        if parameter.name == 'period' and parameter.value <= 0:
            return SetParametersResult(successful=False, reason='period must be greater than 0')
    return SetParametersResult(successful=True)


def main(once: bool, ros_args: list[str]) -> None:
    with zros.init(args=ros_args), Node('parameters_example') as node:
        # Values given with --ros-args -p (or a launch file) override these defaults.
        node.declare_parameter('greeting', 'Hello', ParameterDescriptor(description='what to say'))
        node.declare_parameter('period', 1.0, ParameterDescriptor(description='time between greetings [s]'))
        node.add_on_set_parameters_callback(refuse_bad_period)
        for name in ('greeting', 'period'):
            node.get_logger().info(f'{name}: {node.get_parameter(name).value}')
        result = node.set_parameters([Parameter('period', value=-1.0)])[0]
        node.get_logger().info(f'setting period to -1.0: successful={result.successful}, reason={result.reason!r}')
        if once:
            return

        def greet() -> None:   # reads the parameter each time, so `zros param set` takes effect at once
            node.get_logger().info(node.get_parameter('greeting').value)

        node.create_timer(node.get_parameter('period').value, greet)
        zros.spin(node)


if __name__ == '__main__':
    parser = argparse.ArgumentParser(prog='parameters', description='Declare, validate and use parameters.')
    parser.add_argument('--once', action='store_true', help='print the parameters and exit')
    args = parse_args(parser)
    run(main, args.once)
