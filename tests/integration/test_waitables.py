"""User-defined waitables on zros's executors: asked while the executor waits, run when ready,
in their callback group; and an executor shut down before its context stops quietly."""
from __future__ import annotations

import threading
import time

from zros.callback_groups import MutuallyExclusiveCallbackGroup, ReentrantCallbackGroup
from zros.executors import SingleThreadedExecutor
from zros.node import Node
from zros.task import Future
from zros.waitable import NumberOfEntities, Waitable


class _GuardedWaitable(Waitable):
    """Ready when its guard condition (a zros one, never triggered through the node's own
    callback here) has work; records the calls the executor makes."""

    def __init__(self, node, group) -> None:
        super().__init__(group)
        self.guard = node.create_guard_condition(None)
        self.index = None
        self.calls: list[str] = []
        self.done: Future[str] = Future()

    def add_to_wait_set(self, wait_set) -> None:
        self.index = wait_set.add_guard_condition(self.guard)

    def is_ready(self, wait_set) -> bool:
        return wait_set.is_ready('guard_condition', self.index)

    def take_data(self) -> str:
        self.calls.append('take')
        self.guard._triggered = False   # taken: not ready again for the same trigger
        return 'data'

    async def execute(self, taken_data) -> None:
        self.calls.append(f'execute {taken_data}')
        self.done.set_result(taken_data)

    def get_num_entities(self) -> NumberOfEntities:
        return NumberOfEntities(num_gcs=1)


def test_a_waitable_added_while_spinning_is_asked_and_run(context):
    node = Node('waiter', context=context)
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(node)
    spinner = threading.Thread(target=executor.spin)
    spinner.start()
    try:
        time.sleep(0.2)   # the executor is blocked waiting
        waitable = _GuardedWaitable(node, ReentrantCallbackGroup())
        node.add_waitable(waitable)
        assert list(node.waitables) == [waitable]
        time.sleep(0.1)
        assert waitable.calls == []   # asked, not ready
        waitable.guard._triggered = True   # as the guard's trigger() does, minus the node's callback
        assert waitable.done.wait(2.0)
        assert waitable.calls == ['take', 'execute data']
    finally:
        executor.shutdown()
        spinner.join(5.0)
    node.remove_waitable(waitable)
    assert list(node.waitables) == []


def test_a_waitable_of_a_busy_group_waits(context):
    node = Node('exclusive', context=context)
    group = MutuallyExclusiveCallbackGroup()
    waitable = _GuardedWaitable(node, group)
    node.add_waitable(waitable)
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(node)
    waitable.guard._triggered = True
    assert group.try_enter()
    executor.spin_once(timeout_sec=0.1)
    assert waitable.calls == []
    group.leave()
    executor.spin_once(timeout_sec=1.0)   # takes the data; the coroutine runs as a task
    executor.spin_until_future_complete(waitable.done, timeout_sec=2.0)
    assert waitable.done.result() == 'data'
    executor.shutdown()


def test_an_executor_shut_down_before_its_context_stops_quietly(make_context):
    """rclpy's usual teardown, `executor.shutdown()` then `rclpy.shutdown()`: the spin returns
    without ExternalShutdownException whichever of the two it notices first."""
    errors = []
    for _ in range(3):   # the race is between the spin's two checks: give it a few chances
        context = make_context()
        executor = SingleThreadedExecutor(context=context)

        def spin(executor=executor):
            try:
                executor.spin()
            except BaseException as exc:  # noqa: BLE001 - recorded for the assertion
                errors.append(exc)

        spinner = threading.Thread(target=spin)
        spinner.start()
        time.sleep(0.05)
        executor.shutdown()
        context.shutdown()
        spinner.join(5.0)
    assert errors == []
