"""`zros run topic_tools relay IN [OUT]`: every message of IN again on OUT (default IN_relay).

ROS 2 topic_tools' relay: any type, typed by IN's publishers; parameters input_topic,
output_topic, lazy (subscribe to IN only while OUT has subscribers).
"""
import sys

from nodes.topic_tools._filters import Dropper
from nodes.topic_tools._tool_base import ToolNode, overrides, run

USAGE = 'zros run topic_tools relay IN [OUT]'


class RelayNode(ToolNode):
    def __init__(self, input_topic: str | None = None, output_topic: str | None = None, **kwargs) -> None:
        super().__init__('relay', '_relay', parameter_overrides=overrides(input_topic=input_topic,
                                                                           output_topic=output_topic), **kwargs)

    def make_filter(self) -> Dropper:
        return Dropper(0, 1)      # drop none of every one


def make(positional: list[str]) -> RelayNode:
    if len(positional) > 2:
        raise ValueError(f'too many arguments: {" ".join(positional)}')
    return RelayNode(*positional)


def main(args=None):
    run(make, args, USAGE)


if __name__ == '__main__':
    main(sys.argv)
