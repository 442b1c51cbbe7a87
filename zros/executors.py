"""Executors: the only place user callbacks run.

Zenoh delivers samples on its own threads; those threads only queue the work (an entity with
something to do) on the executor of the entity's node and return. The executor pops work,
runs timers when they are due, and calls the user's callbacks: on the spinning thread
(SingleThreadedExecutor) or on a pool that respects callback groups (MultiThreadedExecutor).
"""
from __future__ import annotations

import os
import queue
import threading
import time
from concurrent.futures import ThreadPoolExecutor
from typing import TYPE_CHECKING, Any, Callable

from zros.subscription import Subscription
from zros.task import Future
from zros.timer import timer_lists_version

if TYPE_CHECKING:
    from zros.node import Node

__all__ = ['Executor', 'SingleThreadedExecutor', 'MultiThreadedExecutor',
           'ExternalShutdownException', 'ShutdownException', 'TimeoutException']


class ExternalShutdownException(Exception):
    """The context was shut down (SIGTERM, `zros.shutdown()` from elsewhere) while spinning."""


ShutdownException = ExternalShutdownException


class TimeoutException(Exception):
    """Kept for rclpy compatibility; zros's spin_once returns instead of raising."""


# Longest single wait, so a blocked spin notices shutdown and signals promptly.
_MAX_WAIT = 0.5
# How many waiting samples spin() lets one subscription deliver per turn: a burst then costs
# one trip through the executor's queue per batch, not per message.
_SPIN_BATCH = 64


class _Task:
    """A plain function to run on the executor (future done-callbacks, create_task)."""

    __slots__ = ('fn', 'args', 'future')
    callback_group = None

    def __init__(self, fn: Callable, args: tuple, future: Future) -> None:
        self.fn, self.args, self.future = fn, args, future

    def _execute(self) -> None:
        try:
            result = self.fn(*self.args)
        except BaseException as exc:
            self.future.set_exception(exc)
            raise
        self.future.set_result(result)


class Executor:
    """Base executor: queue of ready work, timers, nodes. Subclasses decide where work runs."""

    def __init__(self, *, context: Any = None) -> None:
        from zros.context import get_default_context
        self._context = context or get_default_context()
        self._queue: queue.SimpleQueue = queue.SimpleQueue()
        self._nodes: list[Node] = []
        self._nodes_lock = threading.Lock()
        self._spin_lock = threading.Lock()
        self._spin_thread: int | None = None
        self._is_shutdown = False
        self._nodes_version = 0
        self._batch = 1
        self._timers_key: tuple[int, int] | None = None
        self._timers: list = []
        self._context._register_executor(self)

    @property
    def context(self) -> Any:
        return self._context

    # -- nodes -------------------------------------------------------------------------
    def add_node(self, node: 'Node') -> bool:
        with self._nodes_lock:
            if node in self._nodes:
                return False
            self._nodes.append(node)
            self._nodes_version += 1
        node._attach_executor(self)
        self.wake()
        return True

    def remove_node(self, node: 'Node') -> None:
        with self._nodes_lock:
            if node in self._nodes:
                self._nodes.remove(node)
                self._nodes_version += 1
        node._detach_executor(self)
        self.wake()

    def get_nodes(self) -> list['Node']:
        with self._nodes_lock:
            return list(self._nodes)

    # -- work --------------------------------------------------------------------------
    def _enqueue(self, entity: Any) -> None:
        """Called from any thread (mostly Zenoh's) when `entity` has work."""
        self._queue.put(entity)

    def wake(self) -> None:
        self._queue.put(None)

    def create_task(self, callback: Callable, *args: Any) -> Future:
        future = Future()
        self._queue.put(_Task(callback, args, future))
        return future

    def _next_timer(self) -> tuple[Any, int | None]:
        """(due timer or None, ns until the next real-time timer is due or None). Timers on
        simulated time do not count in the wait: /clock updates wake the executor."""
        key = (timer_lists_version(), self._nodes_version)
        if key != self._timers_key:
            self._timers = [t for node in self.get_nodes() for t in node._timers_snapshot()]
            self._timers_key = key
        soonest = None
        for timer in self._timers:
            remaining = timer._remaining_ns()
            if remaining is None:
                continue
            if remaining <= 0:
                group = timer.callback_group
                if group is not None and not group.can_execute(timer):
                    continue  # its group is busy; the executor is woken when the group frees
                if timer._claim():
                    return timer, 0
            elif not timer._on_sim_time and (soonest is None or remaining < soonest):
                soonest = remaining
        return None, soonest

    def _wait_for_work(self, timeout_sec: float | None, until: Callable[[], bool] | None = None) -> Any:
        """Next piece of work, or None when the timeout passes, the executor stops or `until()`
        holds. A bare wake-up (a node added, a future done) only re-checks those, as rclpy's
        guard conditions do: it never ends the wait with nothing done."""
        deadline = None if timeout_sec is None else time.monotonic() + max(0.0, timeout_sec)
        while True:
            self._check_context()
            timer, wait_ns = self._next_timer()
            if timer is not None:
                return timer
            wait = _MAX_WAIT if wait_ns is None else min(_MAX_WAIT, wait_ns / 1e9)
            if deadline is not None:
                wait = min(wait, max(0.0, deadline - time.monotonic()))
            try:
                # A zero wait still takes work already queued (spin_once(timeout_sec=0) polls).
                item = self._queue.get(timeout=wait) if wait > 0 else self._queue.get_nowait()
            except queue.Empty:
                if deadline is not None and time.monotonic() >= deadline:
                    return None
                continue
            if item is None:
                self._check_context()
                if self._stop_waiting() or (until is not None and until()):
                    return None
                continue
            return item

    def _stop_waiting(self) -> bool:
        """Whether a wake-up should end the current wait (subclasses add reasons)."""
        return self._is_shutdown

    def _check_context(self) -> None:
        if not self._context.ok():
            raise ExternalShutdownException()

    def _dispatch(self, item: Any) -> None:
        raise NotImplementedError

    # -- spinning ----------------------------------------------------------------------
    def spin_once(self, timeout_sec: float | None = None) -> None:
        """Run at most one callback, waiting up to `timeout_sec` (None: until one is ready)."""
        with self._spinning():
            self._spin_once(timeout_sec)

    def _spin_once(self, timeout_sec: float | None, until: Callable[[], bool] | None = None) -> bool:
        if timeout_sec is None:
            item = None
            while item is None:
                item = self._wait_for_work(None, until)
                if self._is_shutdown or (item is None and until is not None and until()):
                    return False
        else:
            item = self._wait_for_work(timeout_sec, until)
            if item is None:
                return False
        self._dispatch(item)
        return True

    def spin(self) -> None:
        with self._spinning():
            self._batch = _SPIN_BATCH
            try:
                while not self._is_shutdown:
                    self._spin_once(_MAX_WAIT)
            finally:
                self._batch = 1

    def spin_until_future_complete(self, future: Future, timeout_sec: float | None = None) -> None:
        self._adopt(future)
        with self._spinning():
            deadline = None if timeout_sec is None else time.monotonic() + timeout_sec
            while not future.done() and not self._is_shutdown:
                remaining = _MAX_WAIT if deadline is None else min(_MAX_WAIT, deadline - time.monotonic())
                if remaining <= 0:
                    return
                self._spin_once(remaining, future.done)

    def spin_once_until_future_complete(self, future: Future, timeout_sec: float | None = None) -> None:
        self._adopt(future)
        with self._spinning():
            if not future.done():
                self._spin_once(timeout_sec, future.done)

    def _adopt(self, future: Future) -> None:
        """Make the future wake this executor when it completes (from any thread)."""
        if getattr(future, '_executor', None) is None:
            future._set_executor(self)

    def _spinning(self) -> '_SpinGuard':
        return _SpinGuard(self)

    def _wait_until_idle(self, timeout_sec: float) -> bool:
        """Wait (from another thread) until no callback of this executor is running, so that a
        context shutdown does not pull the nodes from under it; False on timeout."""
        if self._spin_thread == threading.get_ident():
            return False  # shut down from inside one of our own callbacks
        if not self._spin_lock.acquire(timeout=timeout_sec):
            return False
        self._spin_lock.release()
        return True

    def shutdown(self, timeout_sec: float | None = None) -> bool:
        """Stop spinning and detach the nodes; returns True (nothing is left running)."""
        self._is_shutdown = True
        self.wake()
        for node in self.get_nodes():
            self.remove_node(node)
        self._context._unregister_executor(self)
        return True


class _SpinGuard:
    def __init__(self, executor: Executor) -> None:
        self._executor = executor

    def __enter__(self) -> None:
        if not self._executor._spin_lock.acquire(blocking=False):
            raise RuntimeError('Executor is already spinning')
        self._executor._spin_thread = threading.get_ident()

    def __exit__(self, *exc: object) -> None:
        self._executor._spin_thread = None
        self._executor._spin_lock.release()


class SingleThreadedExecutor(Executor):
    """Runs every callback on the thread that spins, one at a time, in arrival order."""

    def _dispatch(self, item: Any) -> None:
        if self._batch > 1 and type(item) is Subscription:
            item._execute(self._batch)
        else:
            item._execute()


class MultiThreadedExecutor(Executor):
    """Runs callbacks on a thread pool; a MutuallyExclusiveCallbackGroup runs one at a time.

    Work for a busy exclusive group waits in that group's backlog and is queued again when
    the running callback returns, so no pool thread ever blocks on a group.
    """

    def __init__(self, num_threads: int | None = None, *, context: Any = None) -> None:
        super().__init__(context=context)
        if num_threads is None:
            try:
                num_threads = len(os.sched_getaffinity(0))
            except (AttributeError, OSError):
                num_threads = os.cpu_count() or 2
        self._num_threads = max(1, num_threads)
        self._pool = ThreadPoolExecutor(max_workers=self._num_threads, thread_name_prefix='zros-exec')
        self._backlog: dict[int, list[Any]] = {}
        self._backlog_lock = threading.Lock()
        self._errors: queue.SimpleQueue = queue.SimpleQueue()

    @property
    def num_threads(self) -> int:
        return self._num_threads

    def _dispatch(self, item: Any) -> None:
        self._raise_pending_error()
        group = getattr(item, 'callback_group', None)
        if group is not None and not group.try_enter():
            with self._backlog_lock:
                self._backlog.setdefault(id(group), []).append(item)
            # The running callback may have finished between try_enter and the append.
            if group.try_enter():
                self._pool.submit(self._run, item=None, group=group)
            return
        self._pool.submit(self._run, item=item, group=group)

    def _run(self, item: Any, group: Any) -> None:
        try:
            while True:
                if item is not None:
                    item._execute()
                if group is None:
                    return
                with self._backlog_lock:
                    backlog = self._backlog.get(id(group))
                    item = backlog.pop(0) if backlog and not self._is_shutdown else None
                if item is None:
                    group.leave()
                    # Wake the spinning thread: a timer of this group may be due by now.
                    self.wake()
                    # Work may have been parked after we looked; run it here.
                    with self._backlog_lock:
                        if self._backlog.get(id(group)) and not self._is_shutdown and group.try_enter():
                            continue
                    return
        except BaseException as exc:  # surfaced on the spinning thread, as rclpy does
            if group is not None:
                group.leave()
            self._errors.put(exc)
            self.wake()

    def _raise_pending_error(self) -> None:
        try:
            exc = self._errors.get_nowait()
        except queue.Empty:
            return
        raise exc

    def _stop_waiting(self) -> bool:
        return super()._stop_waiting() or not self._errors.empty()

    def _spin_once(self, timeout_sec: float | None, until: Callable[[], bool] | None = None) -> bool:
        self._raise_pending_error()
        return super()._spin_once(timeout_sec, until)

    def shutdown(self, timeout_sec: float | None = None) -> bool:
        result = super().shutdown(timeout_sec)
        with self._backlog_lock:
            self._backlog.clear()
        self._pool.shutdown(wait=timeout_sec is None or timeout_sec > 0, cancel_futures=True)
        return result
