"""Executors: the only place user callbacks run.

Zenoh delivers samples on its own threads; those threads only queue the work (an entity with
something to do) on the executor of the entity's node and return. The executor takes work from
that queue, runs timers when they are due, and calls the user's callbacks: on the spinning
thread (SingleThreadedExecutor), on a thread pool (MultiThreadedExecutor), or wherever a
subclass sends the handlers that `wait_for_ready_callbacks` returns (rclpy's extension point).

How one piece of work runs (`_run_item`): it takes its callback group, or waits in the group's
backlog while another callback holds it (the backlog goes back on the queue when the group is
left); it runs; a callback that returns a coroutine (`async def`) continues as a Task that keeps
the group until the coroutine ends (zros.task).

Where work comes from, in the order it is taken: tasks made by `create_task` that have not run
yet (newest first, as rclpy yields its tasks), due timers, the user waitables of the nodes
(zros.waitable, asked in turn whenever the executor looks for work), then the queue.

The pull (docs/architecture.md §3): a sample handed from the subscription's pump thread to the
spinning thread costs a thread wake-up more than raw zenoh-python's callback, more than all of
zros's other work on it. So while a SingleThreadedExecutor's `spin()` (or
`spin_until_future_complete()` without a timeout) serves nodes with exactly one subscription
and no timer or user waitable, the spinning thread blocks on that subscription's Zenoh channel
itself (the interpreter lock released in Zenoh, as raw zenoh-python's own receive does) and runs
the callback as soon as it wakes, inside the subscription's group, on the thread that spins, as
rclpy runs it. Whatever else gives this executor work (a service request, a guard condition, a
task, a completed future, a wake-up, shutdown) queues it as usual and then wakes the channel
with an empty sample put on the topic's key for this session only (`_enqueue_pulling`); the
spin takes the queued work first. A new subscription, timer or node ends the pull at the next
wake-up and the pump receives again. `spin_once` and MultiThreadedExecutors keep the hand-off.

Leader/follower (docs/architecture.md §3; opt-in, ZROS_CALLBACK_THREAD=zenoh): a thread hop
costs more than the rest of zros's work per message, so while a SingleThreadedExecutor's
`spin()` or `spin_until_future_complete()` is parked on its queue, a subscription's sample that
comes after a quiet spell is run at once by the thread it arrived on (zenoh-python's callback
thread), which takes the executor's token (`_token`) for it: the spinning thread takes the same
token before it runs anything, so callbacks still run one at a time, inside their groups, with
the executor's accounting. Anything else takes the hand-off through the queue: a sample that
arrives while the executor is busy, and a sample close behind the previous one (a burst,
zros.subscription), since leading a flood would put receiving and running on one thread where
the hand-off lets Zenoh's thread receive the next sample while the executor runs this one
(leading every sample halved KEEP_ALL throughput, docs/benchmarks-history.md, "Issue 35").
`spin_once` never lets a sample be led (it returns after one callback of its own); neither does
a MultiThreadedExecutor, nor a subclass with its own `spin_once`, nor a pulled subscription (the
pull has no hop to save).
"""
from __future__ import annotations

import collections
import contextlib
import inspect
import os
import queue
import threading
import time
import warnings
from time import perf_counter as _clock
from concurrent.futures import ThreadPoolExecutor
from typing import TYPE_CHECKING, Any, Callable, Iterator

from zros.subscription import _HAND_OFF_S, _LEAD_QUICK_S, Subscription, subscription_lists_version
from zros.task import Future, Task
from zros.timer import timer_lists_version
from zros.waitable import POLL_PERIOD, WaitSet, waitable_lists_version

if TYPE_CHECKING:
    from zros.node import Node

__all__ = ['Executor', 'SingleThreadedExecutor', 'MultiThreadedExecutor', 'ExternalShutdownException',
           'ShutdownException', 'TimeoutException', 'ConditionReachedException', 'spin_nodes']


class ExternalShutdownException(Exception):
    """The context was shut down (a signal, `zros.shutdown()` from elsewhere) while spinning."""


class ShutdownException(Exception):
    """This executor was shut down while waiting for work."""


class TimeoutException(Exception):
    """`wait_for_ready_callbacks` found no work within its timeout."""


class ConditionReachedException(Exception):
    """`wait_for_ready_callbacks` returned because its condition came true."""


# Longest single wait, so a blocked spin notices shutdown and signals promptly.
_MAX_WAIT = 0.5
# How many waiting samples spin() lets one subscription deliver per turn: a burst then costs
# one trip through the executor's queue per batch, not per message.
_SPIN_BATCH = 64
# ZROS_CALLBACK_THREAD: 'spin' (the default), every callback on the spinning thread, as rclpy
# runs them (a GUI toolkit or thread-local state in a callback relies on it); 'zenoh',
# leader/follower (checked with the other settings at init: zros.config)
def _leading_allowed(setting: str | None) -> bool:
    return (setting or '').strip() == 'zenoh'


_LEADING_ALLOWED = _leading_allowed(os.environ.get('ZROS_CALLBACK_THREAD'))


class _Completion:
    """Work that is only news: a future completed (spin_once returns on it, as rclpy's does when
    it takes a client's response)."""

    callback_group = None
    _node = None

    @staticmethod
    def _execute() -> None:
        return None


_COMPLETION = _Completion()


class _WaitableRun:
    """One run of a ready user waitable (zros.waitable): take its data, then execute it; an
    `async def execute` comes back as a coroutine, which `_run_item` runs as a task."""

    def __init__(self, waitable: Any, node: Any) -> None:
        self.callback_group = waitable.callback_group
        self._node = node
        self._waitable = waitable

    def _execute(self) -> Any:
        waitable = self._waitable
        waitable._executor_event = False
        with waitable:
            taken = waitable.take_data()
        return waitable.execute(taken)


class Executor:
    """Base executor: the queue of ready work, timers and nodes. Subclasses decide where work
    runs; a user subclass overrides `spin_once` and takes work from `wait_for_ready_callbacks`.
    """

    # Callbacks run on the thread that waits for work (a subclass that hands them to other
    # threads says False): a full KEEP_LAST queue may then wait for this thread (Subscription).
    _runs_on_waiting_thread = True

    def __init__(self, *, context: Any = None) -> None:
        from zros.context import get_default_context
        self._context = context or get_default_context()
        self._queue: queue.SimpleQueue = queue.SimpleQueue()
        # Called from any thread (mostly Zenoh's, once per sample after a quiet spell) when a
        # piece of work is ready to run: the queue's own put, so that handing work over runs no
        # Python of the executor's on Zenoh's thread, which holds the interpreter lock the
        # woken executor is about to need.
        self._enqueue: Callable[[Any], None] = self._queue.put
        self._nodes: list[Node] = []
        self._nodes_lock = threading.Lock()
        self._spin_lock = threading.RLock()
        self._spin_thread: int | None = None
        self._is_shutdown = False
        self._nodes_version = 0
        self._batch = 1
        self._idle = False   # blocked on its queue, or just woken from it: no callback running
        self._timers_key: tuple[int, int, int] | None = None   # the lists below are of this version
        self._timers: list = []
        self._waitables: list[tuple[Any, Any]] = []   # (waitable, its node)
        self._backlog: dict[int, list[Any]] = {}    # id(group) -> work waiting for that group
        self._backlog_lock = threading.Lock()
        self._timer_blocked = False   # a due timer was passed over because its group was busy
        # Tasks made by create_task that have not run yet: taken newest first, before other work,
        # as rclpy's executor yields its tasks (a task made to await an earlier one runs first).
        self._new_tasks: collections.deque[Task[Any]] = collections.deque()
        # Leader/follower (module docstring): whoever runs a callback holds the token; `_leading`
        # while a spin may be led, `_leader` the thread that leads now.
        self._token = threading.RLock()
        self._leading = False
        self._leader: int | None = None
        self._errors: queue.SimpleQueue = queue.SimpleQueue()   # raised again on the spinning thread
        # The pull (module docstring): the one subscription spin() may receive from itself, for
        # the lists of this key; `_pulling` while blocked on its channel, `_poked` once woken.
        self._pull_key: tuple[int, int, int, int] | None = None
        self._pull_sub: Subscription | None = None
        self._pulling = False
        self._poked = False
        self._context._register_executor(self)

    @property
    def context(self) -> Any:
        """The Context whose shutdown stops this executor's spinning."""
        return self._context

    # -- nodes -------------------------------------------------------------------------
    def add_node(self, node: 'Node') -> bool:
        """Make this executor run the callbacks of `node`.

        The node's pending work (messages that arrived while no executor had it, completed futures)
        is queued at once, so the next spin runs it.

        :param node: The node to add.
        :return: ``True`` if the node was added, ``False`` if it already was.
        """
        with self._nodes_lock:
            if node in self._nodes:
                return False
            self._nodes.append(node)
            self._nodes_version += 1
        node._attach_executor(self)
        self.wake()
        return True

    def remove_node(self, node: 'Node') -> None:
        """Stop running the callbacks of `node`; nothing happens if it was not added.

        :param node: The node to remove.
        """
        with self._nodes_lock:
            if node in self._nodes:
                self._nodes.remove(node)
                self._nodes_version += 1
        node._detach_executor(self)
        self.wake()

    def get_nodes(self) -> list['Node']:
        """The nodes this executor spins.

        :return: A copy of the list, safe to iterate while nodes are added or removed.
        """
        with self._nodes_lock:
            return list(self._nodes)

    # -- work --------------------------------------------------------------------------
    def wake(self) -> None:
        """Make the executor look again (at timers, nodes, shutdown); not itself work."""
        self._enqueue(None)

    def _note_completion(self) -> None:
        self._enqueue(_COMPLETION)

    def _enqueue_pulling(self, item: Any) -> None:
        """`_enqueue` while spin() pulls: queue the work, and wake the spinning thread if it
        blocks on the subscription's channel (once per block: a second wake-up adds nothing)."""
        self._queue.put(item)
        if self._pulling and not self._poked:
            self._poked = True
            subscription = self._pull_sub
            if subscription is not None:
                subscription._poke()

    def _lead(self, entity: Any) -> bool:
        """Zenoh's thread, with a sample just queued on `entity` (a Subscription): run it here
        and now if the executor is parked in a spin that may be led (module docstring), and say
        whether it did; False leaves the hand-off to the caller. An exception from the callback
        is raised again on the spinning thread, as one from the spinning thread would be."""
        if not self._idle or not self._token.acquire(blocking=False):
            return False
        try:
            if not (self._idle and self._leading) or self._is_shutdown:
                return False   # (it woke meanwhile: the hand-off keeps the order of its work)
            self._leader = threading.get_ident()
            entity._scheduled = True   # (its `_execute` re-arms it)
            start = time.perf_counter()
            try:
                self._run_item(entity)   # (one sample: the queue was empty before it came)
            except BaseException as exc:
                self._errors.put(exc)
                self.wake()
            finally:
                self._leader = None
                end = time.perf_counter()
                entity._last_seen = end   # (a sample waiting behind this one is a burst)
                took = end - start
                if took > _LEAD_QUICK_S or entity._lead_slow:
                    entity._note_led(took)
            return True
        finally:
            self._token.release()

    def _wait_for_leader(self) -> None:
        """Block until no leader runs a callback (the token is free)."""
        with self._token:
            pass

    def _raise_pending_error(self) -> None:
        if self._errors.empty():   # (the common case, each turn of a spin: no exception made)
            return
        try:
            exc = self._errors.get_nowait()
        except queue.Empty:
            return
        raise exc

    def create_task(self, callback: Callable | Any, *args: Any, **kwargs: Any) -> Task:
        """Run `callback(*args, **kwargs)` on this executor, outside any callback group.

        :param callback: A function, a coroutine function or a coroutine.
        :param args: Positional arguments for `callback`.
        :param kwargs: Keyword arguments for `callback`.
        :return: The Task, a Future of the callback's return value.
        """
        task: Task[Any] = Task(callback, args, kwargs, executor=self)
        self._new_tasks.append(task)
        self.wake()
        return task

    def _next_timer(self) -> tuple[Any, int | None]:
        """(due timer or None, ns until the next real-time timer is due or None). Timers on
        simulated time do not count in the wait: /clock updates wake the executor. Also brings
        the list of the nodes' waitables up to date."""
        key = (timer_lists_version(), waitable_lists_version(), self._nodes_version)
        if key != self._timers_key:
            nodes = self.get_nodes()
            self._timers = [t for node in nodes for t in node._timers_snapshot()]
            self._waitables = [(w, node) for node in nodes for w in node.waitables]
            self._timers_key = key
        soonest = None
        for timer in self._timers:
            remaining = timer._remaining_ns()
            if remaining is None:
                continue
            if remaining <= 0:
                group = timer.callback_group
                if group is not None and not group.can_execute(timer):
                    self._timer_blocked = True   # the next group left wakes the executor
                    if not group.can_execute(timer):   # (unless it was left just now)
                        continue
                if timer._claim():
                    return timer, 0
            elif not timer._on_sim_time and (soonest is None or remaining < soonest):
                soonest = remaining
        return None, soonest

    def _ready_waitable(self) -> _WaitableRun | None:
        """Ask each waitable whose group is free whether it is ready (zros.waitable's contract)."""
        for waitable, node in self._waitables:
            group = waitable.callback_group
            if waitable._executor_event or (group is not None and not group.can_execute(waitable)):
                continue
            wait_set = WaitSet()
            with waitable:
                waitable.add_to_wait_set(wait_set)
                ready = waitable.is_ready(wait_set)
            if ready:
                waitable._executor_event = True
                return _WaitableRun(waitable, node)
        return None

    def _wait_for_work(self, timeout_sec: float | None, until: Callable[[], bool] | None = None) -> Any:
        """Next piece of work, or None when the timeout passes, the executor stops or `until()`
        holds. A bare wake-up (a node added, a group freed) only re-checks those, as rclpy's
        guard conditions do: it never ends the wait with nothing done."""
        deadline = None if timeout_sec is None else time.monotonic() + max(0.0, timeout_sec)
        while True:
            if self._is_shutdown:
                return None
            self._check_context()
            if self._new_tasks:
                try:
                    return self._new_tasks.pop()
                except IndexError:   # another pool thread took it
                    pass
            timer, wait_ns = self._next_timer()
            if timer is not None:
                return timer
            wait = _MAX_WAIT if wait_ns is None else min(_MAX_WAIT, wait_ns / 1e9)
            if self._waitables:   # (brought up to date by _next_timer)
                run = self._ready_waitable()
                if run is not None:
                    return run
                wait = min(wait, POLL_PERIOD)
            if deadline is not None:
                wait = min(wait, max(0.0, deadline - time.monotonic()))
            try:
                # A zero wait still takes work already queued (spin_once(timeout_sec=0) polls).
                self._idle = True
                try:
                    item = self._queue.get(timeout=wait) if wait > 0 else self._queue.get_nowait()
                finally:
                    self._idle = False
            except queue.Empty:
                if deadline is not None and time.monotonic() >= deadline:
                    return None
                continue
            leader = self._leader
            if leader is not None and leader != threading.get_ident():
                # A leader runs a callback: leave the item to it (a spin nested in that callback
                # waits for it) and wait until it is done.
                self._queue.put(item)
                self._wait_for_leader()
                continue
            if item is None:
                self._check_context()
                if self._stop_waiting() or (until is not None and until()):
                    return None
                continue
            return item

    def _stop_waiting(self) -> bool:
        """Whether a wake-up should end the current wait: shutdown, or an error to raise."""
        return self._is_shutdown or not self._errors.empty()

    def _check_context(self) -> None:
        # An executor shut down before its context stops quietly, whichever its spin sees first.
        if not self._context.ok() and not self._is_shutdown:
            raise ExternalShutdownException()

    # -- running work ----------------------------------------------------------------------
    def _run_item(self, item: Any, batch: int = 1) -> None:
        """Run one piece of work on this thread, inside its callback group (see the module
        docstring). Exceptions from the callback propagate."""
        group = item.callback_group
        if group is not None and not group.try_enter(item):
            self._park(group, item)
            return
        pending = None
        try:
            pending = item._execute(batch) if batch > 1 and type(item) is Subscription else item._execute()
        finally:
            if group is not None and (pending is None or not inspect.iscoroutine(pending)):
                self._leave_group(group, item)
        if pending is not None and inspect.iscoroutine(pending):
            Task(pending, executor=self, node=getattr(item, '_node', None), callback_group=group)._execute()

    def _park(self, group: Any, item: Any) -> None:
        with self._backlog_lock:
            self._backlog.setdefault(id(group), []).append(item)
        if group.can_execute():   # it was left between try_enter and the append
            self._release_backlog(group)

    def _leave_group(self, group: Any, entity: Any = None) -> None:
        group.leave(entity)
        self._release_backlog(group)
        if self._timer_blocked:
            self._timer_blocked = False
            self.wake()   # a timer of this group may be due by now

    def _release_backlog(self, group: Any) -> None:
        if not self._backlog:
            return   # (a callback parked meanwhile sees its group free and releases itself)
        with self._backlog_lock:
            parked = self._backlog.pop(id(group), ())
        for item in parked:
            self._enqueue(item)

    def _dispatch(self, item: Any) -> None:
        raise NotImplementedError

    # -- the pull ---------------------------------------------------------------------------
    def _pull_candidate(self) -> Subscription | None:
        """The subscription spin() receives from itself (module docstring): the only one of
        this executor's nodes, pullable, while they have no timer and no waitable and the
        executor runs its callbacks on the spinning thread; None otherwise. Recomputed only
        when a list it depends on changed."""
        key = (subscription_lists_version(), timer_lists_version(), waitable_lists_version(),
               self._nodes_version)
        if key != self._pull_key:
            self._pull_key = key
            self._pull_sub = self._find_pull_candidate()
        return self._pull_sub

    def _find_pull_candidate(self) -> Subscription | None:
        if not (self._runs_on_waiting_thread and self._builtin_spin_once()):
            return None
        found = None
        for node in self.get_nodes():
            if node._timers_snapshot() or any(True for _ in node.waitables):
                return None
            for entity in list(node._entities):
                if isinstance(entity, Subscription):
                    if found is not None or not entity._pullable:
                        return None
                    found = entity
        return found

    def _spin_pulling(self, subscription: Subscription, until: Callable[[], bool] | None = None) -> None:
        """spin() while `subscription` is the pull candidate: its pump steps aside and this
        thread blocks on the subscription's Zenoh channel itself, so that a sample wakes the
        thread that runs its callback directly (one thread wake-up, as raw zenoh-python's own
        callback costs) instead of waking the pump and then this thread. Everything else that
        has work for this executor queues it as usual and then wakes the channel
        (`_enqueue_pulling`). Returns when the executor shuts down, `until()` holds, the
        candidate changes or the channel closes; the pump then receives again."""
        if not subscription._take_channel():
            self._pull_sub = None   # (not again until the lists change)
            return
        self._enqueue = self._enqueue_pulling
        waiting = self._queue
        receive = subscription._zenoh.recv
        try:
            while not self._is_shutdown:
                # (whatever changes the candidate, ends the wait or raises comes with queued work)
                if not waiting.empty() or self._new_tasks:
                    if self._pull_candidate() is not subscription or (until is not None and until()):
                        return
                    self._raise_pending_error()
                    item = self._wait_for_work(0.0, until)   # (takes what is queued, no waiting)
                    if item is not None:
                        self._dispatch(item)
                    continue
                self._poked = False
                self._pulling = True
                if not waiting.empty() or self._new_tasks or self._is_shutdown:
                    self._pulling = False   # (queued before the flag was up: no wake-up comes)
                    continue
                try:
                    sample = receive()   # (blocks, the interpreter lock released in Zenoh)
                except Exception:  # noqa: BLE001 - zenoh.ZError: the channel is closed
                    sample = None
                finally:
                    self._pulling = False
                if sample is None:   # (the channel is closed)
                    self._pull_sub = None
                    return
                if (subscription._plain and subscription._events is None and not subscription._queue
                        and not subscription._absent):
                    self._deliver_pulled(subscription, sample)
                    continue
                subscription._queue_pulled(sample, self._batch)
                if subscription._queue and not subscription._scheduled:
                    subscription._scheduled = True   # (its `_execute` re-arms it)
                    self._dispatch(subscription)
        finally:
            self._enqueue = waiting.put
            subscription._give_channel()

    def _deliver_pulled(self, subscription: Subscription, sample: Any) -> None:
        """The pull's own delivery, for the common case (a callback that takes the message
        only, no QoS event to track, nothing queued): `sample` and those behind it in the
        channel go to the callback straight from the channel, inside the subscription's
        group, without passing through its queue. It stops after the turn's budget, when
        other work is queued, when a callback returned a coroutine (it runs as a task that
        keeps the group), and after a slow callback, so that the next take finds the channel
        as the pump's KEEP_LAST would have left it (`_queue_pulled`)."""
        group = subscription.callback_group
        # (no token: nothing leads while the executor pulls, its one subscription's pump parked)
        if group is not None and not group.try_enter(subscription):
            subscription._queue_pulled(sample, self._batch)
            subscription._scheduled = True
            self._park(group, subscription)
            return
        deliver = subscription._deliver_plain
        receive = subscription._zenoh.try_recv
        waiting = self._queue
        budget = self._batch
        pending = None
        taken = _clock()
        slow = False
        try:
            while True:
                pending = deliver(sample)
                now = _clock()
                if now - taken > _HAND_OFF_S:   # (a slow callback: `_queue_pulled` takes over)
                    slow = True
                    break
                if pending is not None and inspect.iscoroutine(pending):
                    break
                budget -= 1
                if budget <= 0 or not waiting.empty():
                    break
                try:
                    sample = receive()
                except Exception:  # noqa: BLE001 - zenoh.ZError: closed (destroyed in the callback)
                    break
                if sample is None:
                    break
                taken = now
        finally:
            subscription._last_pull = taken
            subscription._absent = slow
            if group is not None and (pending is None or not inspect.iscoroutine(pending)):
                self._leave_group(group, subscription)
        if pending is not None and inspect.iscoroutine(pending):
            Task(pending, executor=self, node=subscription._node, callback_group=group)._execute()

    # -- rclpy's extension point -------------------------------------------------------------
    def wait_for_ready_callbacks(self, timeout_sec: float | None = None, nodes: list | None = None,
                                 condition: Callable[[], bool] | None = None) -> tuple[Task, Any, Any]:
        """(handler, entity, node) for the next piece of work: calling the handler runs it
        (in its callback group) on the calling thread, so a custom executor may run handlers
        wherever it likes. Raises TimeoutException after `timeout_sec` (None: wait for work),
        ShutdownException when this executor is shut down, ExternalShutdownException when the
        context is, ConditionReachedException when `condition()` came true.

        `nodes`: zros waits on all the executor's nodes; give an executor only the nodes it
        should wait on."""
        if nodes is not None:
            raise NotImplementedError('wait_for_ready_callbacks(nodes=...) is not supported: add only '
                                      'those nodes to this executor')
        if self._is_shutdown:
            raise ShutdownException()
        item = self._wait_for_work(timeout_sec, condition)
        if item is None:
            if self._is_shutdown:
                raise ShutdownException()
            if condition is not None and condition():
                raise ConditionReachedException()
            raise TimeoutException()
        return Task(self._run_item, (item,), executor=self), item, getattr(item, '_node', None)

    def _wait_for_ready_callbacks(self, timeout_sec: float | None = None, nodes: list | None = None,
                                  condition: Callable[[], bool] | None = None
                                  ) -> Iterator[tuple[Task, Any, Any]]:
        """rclpy's generator form of `wait_for_ready_callbacks`, which executors written for
        rclpy iterate: each `next()` waits for one more piece of work, with the same exceptions."""
        while True:
            yield self.wait_for_ready_callbacks(timeout_sec, nodes, condition)

    # -- spinning ----------------------------------------------------------------------
    def spin_once(self, timeout_sec: float | None = None) -> None:
        """Run at most one callback, waiting for one if none is ready.

        A completed client or action future counts as one, so a loop of `spin_once` notices it.

        :param timeout_sec: Seconds to wait for work; ``None`` waits until there is some.
        """
        with self._spinning():
            self._spin_once(timeout_sec)

    def _spin_once(self, timeout_sec: float | None, until: Callable[[], bool] | None = None) -> bool:
        self._raise_pending_error()
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

    def _builtin_spin_once(self) -> bool:
        """Whether spin_once is zros's own (not a user subclass's), so spin may take shortcuts."""
        return type(self).spin_once is Executor.spin_once

    def spin(self) -> None:
        """Run callbacks until the executor or its context is shut down.

        :raises RuntimeError: If this executor is already spinning in another thread.
        """
        with self._spinning():
            if not self._builtin_spin_once():
                while self._context.ok() and not self._is_shutdown:
                    try:
                        self.spin_once()
                    except ShutdownException:
                        return
                self._check_context()
                return
            self._batch = _SPIN_BATCH
            with self._led():
                try:
                    while not self._is_shutdown:
                        subscription = self._pull_candidate()
                        if subscription is not None:
                            self._spin_pulling(subscription)
                        else:
                            self._spin_once(_MAX_WAIT)
                finally:
                    self._batch = 1

    def spin_until_future_complete(self, future: Future, timeout_sec: float | None = None) -> None:
        """Run callbacks until `future` completes, the timeout passes or the context shuts down.

        The future need not belong to one of the executor's nodes: a future with no executor of its
        own is given this one, so its completion wakes the spin.

        :param future: The future to wait for.
        :param timeout_sec: Seconds to wait at most; ``None`` waits forever.
        """
        self._adopt(future)
        with self._spinning(), self._led():
            deadline = None if timeout_sec is None else time.monotonic() + timeout_sec
            while not future.done() and not self._is_shutdown:
                remaining = _MAX_WAIT if deadline is None else min(_MAX_WAIT, deadline - time.monotonic())
                if remaining <= 0:
                    return
                if not self._builtin_spin_once():
                    self.spin_once(remaining)
                    continue
                # (pulling waits for the completion's wake-up: only if it comes to this executor)
                pull = deadline is None and getattr(future, '_current_executor', lambda: None)() is self
                subscription = self._pull_candidate() if pull else None
                if subscription is not None:
                    self._spin_pulling(subscription, future.done)
                else:
                    self._spin_once(remaining, future.done)

    def spin_once_until_future_complete(self, future: Future, timeout_sec: float | None = None) -> None:
        """Run at most one callback, returning early if `future` completes or the timeout passes.

        :param future: The future to wait for.
        :param timeout_sec: Seconds to wait at most for work; ``None`` waits until there is some.
        """
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

    @contextlib.contextmanager
    def _led(self) -> Iterator[None]:
        """Let samples be led while the body spins (if this executor may be led at all), and
        leave only once no leader runs a callback: a shutdown waiting for the spin to end then
        waits for that callback too."""
        previous = self._leading
        self._leading = _LEADING_ALLOWED and self._runs_on_waiting_thread and self._builtin_spin_once()
        try:
            yield
        finally:
            self._leading = previous
            if self._leader != threading.get_ident():
                self._wait_for_leader()

    def _wait_until_idle(self, timeout_sec: float) -> bool:
        """Wait (from another thread) until no callback of this executor is running, so that a
        context shutdown does not pull the nodes from under it; False on timeout."""
        if threading.get_ident() in (self._spin_thread, self._leader):
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
        with self._backlog_lock:
            self._backlog.clear()
        self._context._unregister_executor(self)
        return True

    def __enter__(self) -> 'Executor':
        return self

    def __exit__(self, *exc: object) -> None:
        self.shutdown()


class _SpinGuard:
    """One thread spins an executor at a time; the spinning thread may nest (spin() calls
    spin_once())."""

    def __init__(self, executor: Executor) -> None:
        self._executor = executor

    def __enter__(self) -> None:
        executor = self._executor
        self._in_leader = executor._leader == threading.get_ident()
        if self._in_leader:   # a callback run by a leader spins: nested in the parked spin
            self._outer = False
            return
        if not executor._spin_lock.acquire(blocking=False):
            raise RuntimeError('Executor is already spinning')
        self._outer = executor._spin_thread is None
        executor._spin_thread = threading.get_ident()

    def __exit__(self, *exc: object) -> None:
        if self._in_leader:
            return
        if self._outer:
            self._executor._spin_thread = None
        self._executor._spin_lock.release()


class SingleThreadedExecutor(Executor):
    """Runs callbacks one at a time, in arrival order: on the thread that spins, or, for a
    sample that arrives while `spin()` waits for work, on the thread it arrived on (the module
    docstring's leader/follower)."""

    def _dispatch(self, item: Any) -> None:
        with self._token:
            self._run_item(item, self._batch)


class MultiThreadedExecutor(Executor):
    """Runs callbacks on a thread pool; a MutuallyExclusiveCallbackGroup runs one at a time.

    Work for a busy group waits in that group's backlog and is queued again when the running
    callback leaves the group, so no pool thread ever blocks on a group. An exception in a
    callback is raised again on the spinning thread, as rclpy does.
    """

    _runs_on_waiting_thread = False

    def __init__(self, num_threads: int | None = None, *, context: Any = None) -> None:
        super().__init__(context=context)
        if num_threads is None:
            try:
                num_threads = len(os.sched_getaffinity(0))
            except (AttributeError, OSError):
                num_threads = os.cpu_count() or 2
        self._num_threads = max(1, num_threads)
        if self._num_threads == 1:
            warnings.warn('MultiThreadedExecutor with one thread runs callbacks one at a time: '
                          'use a SingleThreadedExecutor instead', UserWarning, stacklevel=2)
        # Named as rclpy names it (code written for rclpy reads `_executor._max_workers`).
        self._executor = ThreadPoolExecutor(max_workers=self._num_threads, thread_name_prefix='zros-exec')

    @property
    def num_threads(self) -> int:
        """How many worker threads run callbacks in parallel."""
        return self._num_threads

    def _dispatch(self, item: Any) -> None:
        self._raise_pending_error()
        try:
            self._executor.submit(self._run_safely, item)
        except RuntimeError:
            # shutdown() closed the pool after spin took this item: a shut-down executor runs
            # nothing more, so the item is dropped rather than raised out of spin.
            if not self._is_shutdown:
                raise

    def _run_safely(self, item: Any) -> None:
        try:
            self._run_item(item)
        except BaseException as exc:  # surfaced on the spinning thread, as rclpy does
            self._errors.put(exc)
            self.wake()

    def shutdown(self, timeout_sec: float | None = None) -> bool:
        """Stop spinning and shut the worker pool down.

        :param timeout_sec: Seconds to wait for running callbacks; ``None`` waits for them all and
            0 does not wait.
        :return: ``True`` if the executor stopped within the timeout.
        """
        result = super().shutdown(timeout_sec)
        self._executor.shutdown(wait=timeout_sec is None or timeout_sec > 0, cancel_futures=True)
        return result


def spin_nodes(*nodes: Node, num_threads: int = 6) -> None:
    """Spin `nodes` on one MultiThreadedExecutor until shutdown: for a node main whose callbacks
    block (a goal's loop, a service that waits for a topic) or that runs a helper node beside its
    own (a costmap). A zros addition to rclpy's API; as with `zros.spin`, Ctrl-C raises
    KeyboardInterrupt and a shutdown from elsewhere ExternalShutdownException, which the main
    catches around `with zros.init()` so that a signal during start-up ends it quietly too."""
    executor = MultiThreadedExecutor(num_threads=num_threads)
    for node in nodes:
        executor.add_node(node)
    executor.spin()
