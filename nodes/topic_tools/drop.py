"""`zros run topic_tools drop IN X Y [OUT]`: drop X of every Y messages of IN, the rest on OUT
(default IN_drop).

ROS 2 topic_tools' drop: parameters input_topic, output_topic, X, Y, lazy. `drop /scan 2 3`
keeps one scan in three.
"""
import sys

from nodes.topic_tools._filters import Dropper
from nodes.topic_tools._tool_base import ToolNode, overrides, run

USAGE = 'zros run topic_tools drop IN X Y [OUT]'


class DropNode(ToolNode):
    def __init__(self, input_topic: str | None = None, x: int | None = None, y: int | None = None,
                 output_topic: str | None = None, **kwargs) -> None:
        super().__init__('drop', '_drop', parameter_overrides=overrides(input_topic=input_topic, X=x, Y=y,
                                                                         output_topic=output_topic), **kwargs)

    def make_filter(self) -> Dropper:
        return Dropper(int(self.declare_parameter('X', 1).value), int(self.declare_parameter('Y', 2).value))


def make(positional: list[str]) -> DropNode:
    if len(positional) not in (0, 3, 4):
        raise ValueError(f'drop takes IN X Y [OUT], got {len(positional)} arguments')
    if not positional:
        return DropNode()
    try:
        x, y = int(positional[1]), int(positional[2])
    except ValueError:
        raise ValueError(f'X and Y must be integers, got {positional[1]!r} and {positional[2]!r}') from None
    return DropNode(positional[0], x, y, *positional[3:])


def main(args=None):
    run(make, args, USAGE)


if __name__ == '__main__':
    main(sys.argv)
