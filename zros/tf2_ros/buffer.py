"""tf2_ros.Buffer: the frame tree (BufferCore) plus waiting, futures and message transforms.

A TransformListener fills the buffer from Zenoh's receive thread, so a blocking
`lookup_transform(..., timeout=...)` inside a callback works even on a single-threaded
executor (rclpy needs `spin_thread=True` or a second executor for that). Waits block on a
condition that every insert signals, not on a 20 ms poll. Timeouts are wall-clock time, as
rclpy's are.
"""
from __future__ import annotations

import threading
import time as _time
from typing import Any, Callable

from zros.duration import Duration
from zros.task import Future
from zros.tf2_ros.buffer_core import BufferCore
from zros.tf2_ros.buffer_interface import BufferInterface
from zros.time import Time

__all__ = ['Buffer', 'Duration', 'Time']


def _timeout_seconds(timeout: Any) -> float:
    if timeout is None:
        return 0.0
    if isinstance(timeout, Duration):
        return timeout.nanoseconds / 1e9
    if isinstance(timeout, (int, float)):
        return float(timeout)
    return Duration.from_msg(timeout).nanoseconds / 1e9


class Buffer(BufferCore, BufferInterface):
    """Stores known frames; with `node`, serves them on `tf2_frames` (tf2_msgs/srv/FrameGraph).

    Every node holding a Buffer serves that one name, as in ROS, so several servers of it are
    expected and not reported (a Nav2 stack would print one warning per server)."""

    def __init__(self, cache_time: Duration | None = None, node: Any = None) -> None:
        super().__init__(cache_time)
        self._changed = threading.Condition(threading.Lock())
        self._waiters = 0
        self._new_data_callbacks: list[Callable[[], None]] = []
        self._callbacks_lock = threading.Lock()
        self.srv = None
        if node is not None:
            from interfaces.tf2_msgs.srv import FrameGraph

            def frames(request: Any, response: Any) -> Any:
                response.frame_yaml = self.all_frames_as_yaml()
                return response
            self.srv = node.create_service(FrameGraph, 'tf2_frames', frames, expect_other_servers=True)

    # -- waiting -------------------------------------------------------------------------------
    def _on_new_data(self) -> None:
        if self._waiters:
            with self._changed:
                self._changed.notify_all()
        if self._new_data_callbacks:
            with self._callbacks_lock:
                callbacks = list(self._new_data_callbacks)
            for callback in callbacks:
                callback()

    def _wait(self, check: Callable[[], tuple[bool, str]], timeout: Any) -> tuple[bool, str]:
        """Re-check `check` after each insert until it holds or `timeout` passes. The waiter is
        counted before each check, so an insert that lands in between still wakes it."""
        seconds = _timeout_seconds(timeout)
        if seconds <= 0:
            return check()
        deadline = _time.monotonic() + seconds
        with self._changed:
            self._waiters += 1
            try:
                while True:
                    result = check()
                    remaining = deadline - _time.monotonic()
                    if result[0] or remaining <= 0:
                        return result
                    self._changed.wait(remaining)
            finally:
                self._waiters -= 1

    def can_transform(self, target_frame: str, source_frame: str, time: Any, timeout: Any = None,
                      return_debug_tuple: bool = False) -> bool | tuple[bool, str]:
        """Tell whether a transform can be looked up, waiting up to `timeout` for it.

        :param target_frame: The frame to express data in.
        :param source_frame: The frame the data is in.
        :param time: The time of the transform; ``Time()`` for the latest common time.
        :param timeout: How long to wait (a Duration or seconds); ``None`` does not wait.
        :param return_debug_tuple: Return ``(ok, reason)`` instead of ``ok``.
        :return: ``True`` if it can, or the ``(ok, reason)`` tuple.
        """
        result = self._wait(lambda: self.can_transform_core(target_frame, source_frame, time), timeout)
        return result if return_debug_tuple else result[0]

    def can_transform_full(self, target_frame: str, target_time: Any, source_frame: str, source_time: Any,
                           fixed_frame: str, timeout: Any = None,
                           return_debug_tuple: bool = False) -> bool | tuple[bool, str]:
        """Tell whether a transform between two times can be looked up, waiting up to `timeout`.

        :param target_frame: The frame to express data in.
        :param target_time: The time of the target frame (a Time, or a stamp message).
        :param source_frame: The frame the data is in.
        :param source_time: The time of the source data.
        :param fixed_frame: A frame that does not move between the two times (e.g. ``odom``).
        :param timeout: How long to wait (a Duration or seconds); ``None`` does not wait.
        :param return_debug_tuple: Return ``(ok, reason)`` instead of ``ok``.
        :return: ``True`` if it can, or the ``(ok, reason)`` tuple.
        """
        result = self._wait(lambda: self.can_transform_full_core(target_frame, target_time, source_frame,
                                                                 source_time, fixed_frame), timeout)
        return result if return_debug_tuple else result[0]

    # -- lookups -------------------------------------------------------------------------------
    def lookup_transform(self, target_frame: str, source_frame: str, time: Any, timeout: Any = None) -> Any:
        """The transform taking data from `source_frame` into `target_frame` at `time`.

        The wait blocks on the buffer's condition, which every insert from Zenoh's thread
        signals, so it works inside a callback of a single-threaded executor.

        :param target_frame: The frame to express data in.
        :param source_frame: The frame the data is in.
        :param time: The time of the transform; ``Time()`` for the latest time all links are known.
        :param timeout: How long to wait (a Duration or seconds); ``None`` does not wait.
        :return: A geometry_msgs/msg/TransformStamped.
        :raises LookupException: If a frame is unknown (ConnectivityException,
            ExtrapolationException as tf2), once the timeout has passed; the message says what
            is missing.
        """
        if _timeout_seconds(timeout) > 0:
            self.can_transform(target_frame, source_frame, time, timeout)
        return self.lookup_transform_core(target_frame, source_frame, time)

    def lookup_transform_full(self, target_frame: str, target_time: Any, source_frame: str, source_time: Any,
                              fixed_frame: str, timeout: Any = None) -> Any:
        """The transform taking data from `source_frame` at `source_time` into `target_frame` at
        `target_time`, through `fixed_frame`, waiting up to `timeout` for it.

        :param target_frame: The frame to express data in.
        :param target_time: The time of the target frame.
        :param source_frame: The frame the data is in.
        :param source_time: The time of the source data.
        :param fixed_frame: A frame that does not move between the two times.
        :param timeout: How long to wait (a Duration or seconds); ``None`` does not wait.
        :return: A geometry_msgs/msg/TransformStamped.
        :raises LookupException: If a frame is unknown (also Connectivity- and
            ExtrapolationException, as tf2), once the timeout has passed.
        """
        if _timeout_seconds(timeout) > 0:
            self.can_transform_full(target_frame, target_time, source_frame, source_time, fixed_frame, timeout)
        return self.lookup_transform_full_core(target_frame, target_time, source_frame, source_time, fixed_frame)

    def wait_for_transform_async(self, target_frame: str, source_frame: str, time: Any) -> Future:
        """A Future that completes with ``True`` once the transform can be looked up.

        :param target_frame: The frame to express data in.
        :param source_frame: The frame the data is in.
        :param time: The time of the transform.
        :return: The future, completed by the thread that inserts the missing transform.
        """
        return self._future_for(lambda: self.can_transform_core(target_frame, source_frame, time))

    def wait_for_transform_full_async(self, target_frame: str, target_time: Any, source_frame: str,
                                      source_time: Any, fixed_frame: str) -> Future:
        """A Future that completes with ``True`` once the transform between two times can be looked up.

        The future is completed by the thread that inserts the missing transform (no polling).

        :param target_frame: The frame to express data in.
        :param target_time: The time of the target frame.
        :param source_frame: The frame the data is in.
        :param source_time: The time of the source data.
        :param fixed_frame: A frame that does not move between the two times.
        :return: The future.
        """
        return self._future_for(lambda: self.can_transform_full_core(target_frame, target_time, source_frame,
                                                                     source_time, fixed_frame))

    async def lookup_transform_async(self, target_frame: str, source_frame: str, time: Any) -> Any:
        """Await the transform from `source_frame` into `target_frame` at `time`.

        :param target_frame: The frame to express data in.
        :param source_frame: The frame the data is in.
        :param time: The time of the transform; ``Time()`` for the latest common time.
        :return: A geometry_msgs/msg/TransformStamped.
        """
        await self.wait_for_transform_async(target_frame, source_frame, time)
        return self.lookup_transform_core(target_frame, source_frame, time)

    async def lookup_transform_full_async(self, target_frame: str, target_time: Any, source_frame: str,
                                          source_time: Any, fixed_frame: str) -> Any:
        """Await the transform between two times (see `lookup_transform_full`).

        :param target_frame: The frame to express data in.
        :param target_time: The time of the target frame.
        :param source_frame: The frame the data is in.
        :param source_time: The time of the source data.
        :param fixed_frame: A frame that does not move between the two times.
        :return: A geometry_msgs/msg/TransformStamped.
        """
        await self.wait_for_transform_full_async(target_frame, target_time, source_frame, source_time, fixed_frame)
        return self.lookup_transform_full_core(target_frame, target_time, source_frame, source_time, fixed_frame)

    def _future_for(self, check: Callable[[], tuple[bool, str]]) -> Future[bool]:
        future: Future[bool] = Future()
        if check()[0]:
            future.set_result(True)
            return future

        def on_new_data() -> None:
            if future.done():
                return
            try:
                if check()[0]:
                    future.set_result(True)
            except Exception as exc:  # noqa: BLE001 - handed to whoever awaits the future
                future.set_exception(exc)
            if future.done():
                with self._callbacks_lock:
                    if on_new_data in self._new_data_callbacks:
                        self._new_data_callbacks.remove(on_new_data)

        with self._callbacks_lock:
            self._new_data_callbacks.append(on_new_data)
        on_new_data()  # data may have arrived between the first check and the registration
        return future
