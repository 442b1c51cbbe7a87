"""A Task keeps what its function raised (rclpy.task.Task's contract); the executor's run of it
raises it again so that it comes out of spin."""
from __future__ import annotations

import pytest

from zros.task import Task


class _Boom(Exception):
    pass


def _fail():
    raise _Boom('from a function')


async def _fail_async():
    raise _Boom('from a coroutine')


@pytest.mark.parametrize('handler', [_fail, _fail_async])
def test_calling_a_task_stores_the_exception(handler):
    task = Task(handler)
    task()   # does not raise
    assert task.done() and isinstance(task.exception(), _Boom)
    with pytest.raises(_Boom):
        task.result()


def test_the_executors_run_raises_it_once():
    task = Task(_fail)
    with pytest.raises(_Boom):
        task._execute()
    task._execute()   # done already: nothing runs, nothing is raised again


def test_keyboard_interrupt_still_goes_up():
    def interrupted():
        raise KeyboardInterrupt

    task = Task(interrupted)
    with pytest.raises(KeyboardInterrupt):
        task()
    assert isinstance(task.exception(), KeyboardInterrupt)
