"""Waiting on ROS time for launch_ros's `ROSTimer` when the launch uses sim time.

launch_ros times a ROSTimer with a ROS node of the launch, whose clock follows /clock once
`SetUseSimTime(True)` set its `use_sim_time`. The supervisor has no ROS node (its loop waits on
processes and wall-clock timers), so a sim-time timer gets a `SimTimeWait`: a node of its own on
a thread of its own, which counts the period on the node's clock and tells the supervisor when
it has passed. The period starts at the clock's time when the wait starts, zero until a /clock
message arrives, as a ROS timer created before the first /clock message does.
"""
from __future__ import annotations

import threading
from typing import Callable

__all__ = ['SimTimeWait']

#: [s] how often the waiting thread looks at the clock between /clock messages
_SPIN_TIMEOUT_S = 0.02


class SimTimeWait:
    """`period` seconds of sim time, counted on a thread; `wake` is called once they have
    passed (from that thread), after which `due()` is true.

    Args:
        period: [s] of ROS (sim) time.
        wake: called from the waiting thread when the period has passed.
    """

    def __init__(self, period: float, wake: Callable[[], None]) -> None:
        self.period = period
        self._wake = wake
        self._due = threading.Event()
        self._cancelled = threading.Event()
        self._thread = threading.Thread(target=self._run, name='ros_timer', daemon=True)
        self._thread.start()

    def due(self) -> bool:
        return self._due.is_set()

    def cancel(self) -> None:
        """Stop waiting (the launch is shutting down); returns once the node is gone."""
        self._cancelled.set()
        if self._thread is not threading.current_thread():
            self._thread.join()

    def _run(self) -> None:
        from zros.context import Context
        from zros.executors import SingleThreadedExecutor
        from zros.node import Node
        from zros.parameter import Parameter
        with Context().init([], install_signal_handlers=False) as context:
            node = Node('launch_ros_timer', context=context,
                        parameter_overrides=[Parameter('use_sim_time', value=True)])
            executor = SingleThreadedExecutor(context=context)
            executor.add_node(node)
            clock = node.get_clock()
            start = clock.now().nanoseconds
            period_ns = int(self.period * 1e9)
            while not self._cancelled.is_set():
                if clock.now().nanoseconds - start >= period_ns:
                    self._due.set()
                    self._wake()
                    break
                executor.spin_once(timeout_sec=_SPIN_TIMEOUT_S)
            executor.shutdown()
            node.destroy_node()
