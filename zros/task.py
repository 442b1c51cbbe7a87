"""Futures and tasks, as rclpy.task: a Future is completed by one thread and awaited or polled
by another; a Task runs a function or coroutine on an executor.

`async def` callbacks (timers, subscriptions, services, action execute callbacks, guard
conditions) become Tasks: `await client.call_async(request)` or `await
goal_handle.get_result_async()` suspends the task, the executor runs other callbacks
meanwhile, and the task resumes when the future completes. As in rclpy, a suspended callback
keeps its callback group, so a MutuallyExclusiveCallbackGroup still runs one of its callbacks
at a time. A future of zros's clients completes on Zenoh's thread, so awaiting one never waits
for another callback of the same group (in rclpy that deadlocks).

Done callbacks run on an executor when the future knows one: the executor it was given, or
the executor of its node at the moment it completes (rclpy code often sends a request before it
starts spinning). A completion counts as work for that executor, so `spin_once()` returns on
it, and a node that is not being spun when its future completes hands the completion to the
executor that spins it next. Only a future with neither runs its callbacks in the completing
thread.

A future awaited by anything but a zros Task (an asyncio task, as in rclpy's asyncio examples
that spin the node from the event loop) yields nothing, the way rclpy's futures do, so the
other loop polls it instead of refusing an object it does not know.
"""
from __future__ import annotations

import inspect
import threading
from typing import Any, Callable, Generator, Generic, TypeVar

__all__ = ['Future', 'Task']

# Set while a zros Task steps its coroutine on this thread: only then may __await__ hand the
# future itself to the driver.
_stepping = threading.local()

#: What a Future completes with (`Future[T].result() -> T | None`, as rclpy's).
T = TypeVar('T')


class Future(Generic[T]):
    # Whether completing counts as a piece of work for the executor (a Task's run already does).
    """The outcome of work that completes later, as rclpy.task.Future.

    Any thread may complete it; done callbacks run on the executor it knows (see the module
    docstring). Users get futures from `call_async`, `send_goal_async` and
    `Executor.create_task` rather than making them.

    :param executor: The executor that runs the done callbacks.
    :param node: The node whose executor runs them, looked up when the future completes.
    """
    _marks_work = True

    def __init__(self, *, executor: Any = None, node: Any = None) -> None:
        self._state = 'pending'  # pending | done | cancelled
        self._result: T | None = None
        self._exception: BaseException | None = None
        self._callbacks: list[Callable[['Future[T]'], None]] = []
        self._resume: list['Task'] = []          # tasks suspended on `await self`
        self._lock = threading.Lock()
        self._done_event: threading.Event | None = None
        self._executor = executor
        self._node = node

    def done(self) -> bool:
        """Tell whether the future has completed.

        :return: ``True`` once a result or exception is set, or the future is cancelled.
        """
        return self._state != 'pending'

    def cancelled(self) -> bool:
        """Tell whether the future was cancelled.

        :return: ``True`` after `cancel()` on a pending future.
        """
        return self._state == 'cancelled'

    def cancel(self) -> None:
        """Complete the future as cancelled, if it is still pending; done callbacks run."""
        self._finish('cancelled', None, None)

    def result(self) -> T | None:
        """The result; raises the stored exception; None while pending (as rclpy)."""
        if self._exception is not None:
            raise self._exception
        return self._result

    def exception(self) -> BaseException | None:
        """The exception the work ended with.

        :return: The exception, or ``None`` while pending or after success.
        """
        return self._exception

    def set_result(self, result: T) -> None:
        """Complete the future with `result`; ignored if it is already complete.

        :param result: The value `result()` returns from now on.
        """
        self._finish('done', result, None)

    def set_exception(self, exception: BaseException) -> None:
        """Complete the future with an error; ignored if it is already complete.

        :param exception: The exception `result()` raises from now on.
        """
        self._finish('done', None, exception)

    def _finish(self, state: str, result: Any, exception: BaseException | None) -> None:
        with self._lock:
            if self._state != 'pending':
                return
            self._state, self._result, self._exception = state, result, exception
            callbacks, self._callbacks = self._callbacks, []
            resume, self._resume = self._resume, []
            event = self._done_event
        if event is not None:
            event.set()
        for task in resume:
            task._wake()
        executor = self._current_executor()
        if executor is not None:
            for callback in callbacks:
                executor.create_task(callback, self)
            if not callbacks and self._marks_work:
                executor._note_completion()      # spin_once() returns on it
        elif self._node is not None:
            if self._marks_work:
                self._node._note_completion()    # for whichever executor spins the node next
            for callback in callbacks:
                callback(self)
        else:
            for callback in callbacks:
                callback(self)

    def _current_executor(self) -> Any:
        if self._executor is not None:
            return self._executor
        return getattr(self._node, '_executor', None)

    def add_done_callback(self, callback: Callable[['Future[T]'], None]) -> None:
        """Call `callback(future)` when the future completes (at once if it has).

        The callback runs as a task of the future's executor when it has one, else in the thread
        that completes the future.

        :param callback: A function of one argument, this future.
        """
        with self._lock:
            if self._state == 'pending':
                self._callbacks.append(callback)
                return
        executor = self._current_executor()
        if executor is not None:
            executor.create_task(callback, self)
        else:
            callback(self)

    def _set_executor(self, executor: Any) -> None:
        self._executor = executor

    def _resume_when_done(self, task: 'Task') -> None:
        with self._lock:
            if self._state == 'pending':
                self._resume.append(task)
                return
        task._wake()

    def wait(self, timeout: float | None = None) -> bool:
        """Block this thread until done (not part of rclpy; used by blocking helpers)."""
        with self._lock:
            if self._state != 'pending':
                return True
            if self._done_event is None:
                self._done_event = threading.Event()
            event = self._done_event
        return event.wait(timeout)

    def __await__(self) -> Generator[Any, None, T | None]:
        while not self.done():
            # A zros Task resumes when this future completes; any other driver gets a bare yield.
            yield self if getattr(_stepping, 'task', False) else None
        return self.result()


class Task(Future[T]):
    """Runs a function or a coroutine on an executor (rclpy.task.Task); made by
    `Executor.create_task` and by the executor for `async def` callbacks.

    Calling the task runs the function, or the coroutine up to its next `await` of a pending
    future; the executor calls it again when that future completes. A function that returns
    a coroutine is awaited too (that is how an `async def` callback arrives). A task never
    runs in two threads at once. `callback_group` is the group the task holds until it ends.
    """

    def __init__(self, handler: Any, args: tuple = (), kwargs: dict | None = None, *,
                 executor: Any = None, node: Any = None, callback_group: Any = None) -> None:
        super().__init__(executor=executor, node=node)
        self._handler: Any = handler
        self._args: Any = args
        self._kwargs: Any = kwargs or {}
        self._coroutine: Any = handler if inspect.iscoroutine(handler) else None
        self._held_group = callback_group
        self._executing = False
        self._step_lock = threading.Lock()

    callback_group = None   # a task is run outside any group: it already holds its own
    _marks_work = False

    def executing(self) -> bool:
        """Tell whether the task is running on some thread now.

        :return: ``True`` while the function or a step of the coroutine runs.
        """
        return self._executing

    def __call__(self) -> None:
        """Run or resume the task. An exception the function raises completes the task with it
        (`exception()`, and `result()` raises it), as rclpy's; KeyboardInterrupt and SystemExit
        are stored and also go on up."""
        self._run_step()

    def _execute(self) -> None:
        """Run a step as a piece of executor work: an exception the task ended with in this step
        is raised again, so that it comes out of `spin`, as rclpy's executor raises it."""
        failure = self._run_step()
        if failure is not None:
            raise failure

    def _run_step(self) -> BaseException | None:
        """Run or resume the task; returns the exception it ended with in this step, if any."""
        if self.done() or not self._step_lock.acquire(blocking=False):
            return None
        self._executing = True
        try:
            if self._coroutine is None:
                outcome = self._handler(*self._args, **self._kwargs)
                self._handler = self._args = self._kwargs = None
                if not inspect.iscoroutine(outcome):
                    self._conclude(outcome, None)
                    return None
                self._coroutine = outcome
            self._step()
        except Exception as exc:
            self._conclude(None, exc)
            return exc
        except BaseException as exc:
            self._conclude(None, exc)
            raise
        finally:
            self._executing = False
            self._step_lock.release()
        return None

    def _step(self) -> None:
        outer = getattr(_stepping, 'task', False)
        _stepping.task = True
        try:
            awaited = self._coroutine.send(None)
        except StopIteration as stop:
            self._coroutine = None
            self._conclude(stop.value, None)
            return
        finally:
            _stepping.task = outer
        if isinstance(awaited, Future) and not awaited.done():
            awaited._resume_when_done(self)
        else:
            self._wake()   # a bare `yield` (or an awaitable of another kind): run again soon

    def _conclude(self, result: Any, exception: BaseException | None) -> None:
        self._coroutine = None
        group, self._held_group = self._held_group, None
        executor = self._executor
        if exception is None:
            self.set_result(result)
        else:
            self.set_exception(exception)
        if group is not None and executor is not None:
            executor._leave_group(group)

    def _wake(self) -> None:
        executor = self._executor
        if executor is not None:
            executor._enqueue(self)
