"""tf2_ros.BufferClient: transforms looked up by a buffer server (the `lookup_transform`
action, tf2_msgs/action/LookupTransform) instead of a local Buffer.

For a node that should not hold the whole TF tree itself: the server (tf2_ros's
`buffer_server`, or any node serving the action) keeps the buffer, and each lookup is one goal.
The server's TF2Error comes back as the matching tf2 exception, so callers handle a remote
lookup exactly as a local one.
"""
from __future__ import annotations

import threading
from typing import Any

from zros.duration import Duration
from zros.tf2_ros.buffer import _timeout_seconds
from zros.tf2_ros.buffer_interface import BufferInterface
from zros.tf2_ros.exceptions import (ConnectivityException, ExtrapolationException, InvalidArgumentException,
                                     LookupException, TimeoutException, TransformException)
from zros.time import Time

__all__ = ['BufferClient']

# TF2Error codes -> the exception raised for them (TRANSFORM_ERROR and unknown codes: the base).
_ERRORS = {1: LookupException, 2: ConnectivityException, 3: ExtrapolationException,
           4: InvalidArgumentException, 5: TimeoutException}


def _to_time_msg(time: Any) -> Any:
    return time.to_msg() if isinstance(time, Time) else time


def _to_duration_msg(duration: Any) -> Any:
    if isinstance(duration, (int, float)):
        duration = Duration(seconds=duration)
    return duration.to_msg() if isinstance(duration, Duration) else duration


class BufferClient(BufferInterface):
    """Looks transforms up through the action server `ns` (e.g. 'tf2_buffer_server').

    :param node: the node that owns the action client.
    :param ns: the action's name.
    :param check_frequency: accepted for rclpy compatibility; the wait here is event-driven.
    :param timeout_padding: how much longer than a lookup's own timeout to wait for the server's
        answer before raising TimeoutException.
    """

    def __init__(self, node: Any, ns: str, check_frequency: float = 10.0,
                 timeout_padding: Duration = Duration(seconds=2.0)) -> None:
        from interfaces.tf2_msgs.action import LookupTransform
        from zros.action import ActionClient
        self.node = node
        self._goal_type = LookupTransform.Goal
        self.action_client = ActionClient(node, LookupTransform, action_name=ns)
        self.check_frequency = check_frequency
        self.timeout_padding = timeout_padding

    def lookup_transform(self, target_frame: str, source_frame: str, time: Any,
                         timeout: Duration = Duration()) -> Any:
        """The transform from `source_frame` to `target_frame` at `time`, as the server has it.

        :raises TimeoutException: when the server does not answer in `timeout` plus the padding.
        :raises TransformException: (its subclass for the server's error) when the lookup fails.
        """
        goal = self._goal_type(target_frame=target_frame, source_frame=source_frame,
                               source_time=_to_time_msg(time), timeout=_to_duration_msg(timeout), advanced=False)
        return self._process(goal, timeout)

    def lookup_transform_full(self, target_frame: str, target_time: Any, source_frame: str, source_time: Any,
                              fixed_frame: str, timeout: Duration = Duration()) -> Any:
        """`lookup_transform` through `fixed_frame`, from `source_time` to `target_time`."""
        goal = self._goal_type(target_frame=target_frame, source_frame=source_frame,
                               source_time=_to_time_msg(source_time), target_time=_to_time_msg(target_time),
                               fixed_frame=fixed_frame, timeout=_to_duration_msg(timeout), advanced=True)
        return self._process(goal, timeout)

    def can_transform(self, target_frame: str, source_frame: str, time: Any,
                      timeout: Duration = Duration()) -> bool:
        """Whether the server can give the transform (a failed lookup is False, not raised)."""
        try:
            self.lookup_transform(target_frame, source_frame, time, timeout)
        except TransformException:
            return False
        return True

    def can_transform_full(self, target_frame: str, target_time: Any, source_frame: str, source_time: Any,
                           fixed_frame: str, timeout: Duration = Duration()) -> bool:
        try:
            self.lookup_transform_full(target_frame, target_time, source_frame, source_time, fixed_frame, timeout)
        except TransformException:
            return False
        return True

    def _process(self, goal: Any, timeout: Any) -> Any:
        wait = _timeout_seconds(timeout) + _timeout_seconds(self.timeout_padding)
        if not self.action_client.wait_for_server(timeout_sec=max(wait, 0.001)):
            raise TimeoutException(f"the buffer server '{self.action_client.action_name}' is not running")
        done = threading.Event()
        outcome: list[Any] = []

        def on_result(future: Any) -> None:
            outcome.append(future)
            done.set()

        def on_goal(future: Any) -> None:
            handle = future.result()
            if not handle.accepted:
                outcome.append(None)
                done.set()
                return
            handle.get_result_async().add_done_callback(on_result)

        self.action_client.send_goal_async(goal).add_done_callback(on_goal)
        if not done.wait(max(wait, 0.001)):
            raise TimeoutException(f'the buffer server did not answer within {wait:.2f} s')
        future = outcome[0]
        if future is None:
            raise TransformException('the buffer server refused the lookup')
        result = future.result().result
        if result.error.error != 0:
            raise _ERRORS.get(result.error.error, TransformException)(result.error.error_string)
        return result.transform

    def destroy(self) -> None:
        """Destroy the action client."""
        self.action_client.destroy()
