"""rclpy.utilities equivalents."""
from __future__ import annotations

from zros.arguments import remove_ros_args
from zros.constants import S_TO_NS
from zros.context import get_default_context

__all__ = ['remove_ros_args', 'ok', 'get_default_context', 'timeout_sec_to_nsec',
           'get_rmw_implementation_identifier', 'RMW_IMPLEMENTATION_IDENTIFIER']

#: What `get_rmw_implementation_identifier()` answers: zros is its own middleware, on Zenoh.
RMW_IMPLEMENTATION_IDENTIFIER = 'rmw_zros'


def ok() -> bool:
    """Whether the default context is initialized and not shut down."""
    return get_default_context().ok()


def timeout_sec_to_nsec(timeout_sec: float | None) -> int:
    """`timeout_sec` in nanoseconds, as rcl's waits take it: None or a negative value is -1
    (wait forever), anything under a nanosecond 0."""
    if timeout_sec is None or timeout_sec < 0:
        return -1
    return int(float(timeout_sec) * S_TO_NS)


def get_rmw_implementation_identifier() -> str:
    """The middleware's name (rmw_fastrtps_cpp, rmw_zenoh_cpp ... in ROS): 'rmw_zros'."""
    return RMW_IMPLEMENTATION_IDENTIFIER
