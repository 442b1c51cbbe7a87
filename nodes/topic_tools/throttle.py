"""`zros run topic_tools throttle messages IN RATE [OUT]` or `throttle bytes IN BYTES_PER_SEC WINDOW [OUT]`:
IN again on OUT (default IN_throttle), at most RATE messages a second, or BYTES_PER_SEC bytes
per WINDOW seconds.

ROS 2 topic_tools' throttle, for what crosses a Wi-Fi link: `throttle messages /map 0.2` sends the
map at most every 5 s. Parameters: input_topic, output_topic, throttle_type (messages | bytes),
msgs_per_sec, bytes_per_sec, window, lazy, use_wall_clock (wall time instead of the node's
clock, which follows /clock under use_sim_time).
"""
import sys

from nodes.topic_tools._filters import ByteThrottle, RateThrottle
from nodes.topic_tools._tool_base import Filter, ToolNode, overrides, run

USAGE = 'zros run topic_tools throttle messages IN RATE [OUT] | throttle bytes IN BYTES_PER_SEC WINDOW [OUT]'


class ThrottleNode(ToolNode):
    def __init__(self, throttle_type: str | None = None, input_topic: str | None = None, *, msgs_per_sec=None,
                 bytes_per_sec=None, window=None, output_topic: str | None = None, **kwargs) -> None:
        super().__init__('throttle', '_throttle', parameter_overrides=overrides(
            throttle_type=throttle_type, input_topic=input_topic, msgs_per_sec=msgs_per_sec,
            bytes_per_sec=bytes_per_sec, window=window, output_topic=output_topic), **kwargs)

    def make_filter(self) -> Filter:
        kind = self.declare_parameter('throttle_type', 'messages').value
        if kind == 'messages':
            return RateThrottle(float(self.declare_parameter('msgs_per_sec', 1.0).value))
        if kind == 'bytes':
            return ByteThrottle(int(self.declare_parameter('bytes_per_sec', 1000).value),
                                float(self.declare_parameter('window', 1.0).value))
        raise ValueError(f"throttle_type must be 'messages' or 'bytes', got {kind!r}")


def _number(text: str, what: str, kind=float):
    try:
        return kind(text)
    except ValueError:
        raise ValueError(f'{what} must be a number, got {text!r}') from None


def make(positional: list[str]) -> ThrottleNode:
    if not positional:
        return ThrottleNode()
    kind, rest = positional[0], positional[1:]
    if kind == 'messages' and len(rest) in (2, 3):
        return ThrottleNode(kind, rest[0], msgs_per_sec=_number(rest[1], 'RATE'), output_topic=(rest[2:] or [None])[0])
    if kind == 'bytes' and len(rest) in (3, 4):
        return ThrottleNode(kind, rest[0], bytes_per_sec=_number(rest[1], 'BYTES_PER_SEC', int),
                            window=_number(rest[2], 'WINDOW'), output_topic=(rest[3:] or [None])[0])
    raise ValueError(f'unexpected arguments: {" ".join(positional)}')


def main(args=None):
    run(make, args, USAGE)


if __name__ == '__main__':
    main(sys.argv)
