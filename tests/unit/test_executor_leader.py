"""Leader/follower in the executor (zros.executors): when a sample may be run at once by the
thread it arrived on, and the rules that still hold then (one callback at a time, groups,
errors raised on the spinning thread). No Zenoh: a stub context and stand-in entities."""
from __future__ import annotations

import threading
import time

import pytest

from zros import executors
from zros.callback_groups import MutuallyExclusiveCallbackGroup
from zros.executors import MultiThreadedExecutor, SingleThreadedExecutor
from zros import subscription
from zros.subscription import _BURST_GAP_S, _LEAD_PAUSE, _LEAD_QUICK_S, Subscription


@pytest.fixture(autouse=True)
def _leading(monkeypatch):
    """Leader/follower is opt-in (ZROS_CALLBACK_THREAD=zenoh); these tests hold it on whatever the
    environment says."""
    monkeypatch.setattr(executors, '_LEADING_ALLOWED', True)


class _Context:
    """What an executor asks of its context, without a session."""

    def ok(self) -> bool:
        return True

    def _register_executor(self, executor: object) -> None:
        pass

    def _unregister_executor(self, executor: object) -> None:
        pass


class _Work:
    """Stands in for a subscription with one sample waiting: records the thread that ran it."""

    _node = None
    _scheduled = False
    _lead_slow = True   # (so that every led run is noted)

    def __init__(self, callback=None, group=None) -> None:
        self.callback_group = group
        self.callback = callback or (lambda: None)
        self.threads: list[int] = []
        self.led: list[float] = []

    def _execute(self, budget: int = 1):
        self.threads.append(threading.get_ident())
        self._scheduled = False
        return self.callback()

    def _note_led(self, seconds: float) -> None:
        self.led.append(seconds)


def _parked(executor_type=SingleThreadedExecutor, **kwargs):
    """An executor in the state spin() leaves it in while it waits on its queue."""
    executor = executor_type(context=_Context(), **kwargs)
    executor._leading = executor._runs_on_waiting_thread
    executor._idle = True
    return executor


def test_a_parked_spin_lets_the_arriving_thread_run_the_work_at_once():
    executor, work = _parked(), _Work()
    assert executor._lead(work)
    assert work.threads == [threading.get_ident()]
    assert len(work.led) == 1
    assert executor._leader is None
    assert executor._queue.empty()   # nothing was handed off


@pytest.mark.parametrize('state', ['busy', 'not-leading', 'shut-down'])
def test_no_lead_unless_the_executor_is_parked_in_a_spin_that_allows_it(state):
    executor, work = _parked(), _Work()
    if state == 'busy':
        executor._idle = False
    elif state == 'not-leading':    # spin_once, or ZROS_CALLBACK_THREAD=spin
        executor._leading = False
    else:
        executor._is_shutdown = True
    assert not executor._lead(work)
    assert work.threads == []


def test_a_multi_threaded_executor_is_never_led():
    executor = _parked(MultiThreadedExecutor, num_threads=2)
    try:
        assert not executor._leading
    finally:
        executor.shutdown()


def test_the_spinning_thread_waits_while_a_leader_runs_a_callback():
    """One callback at a time: the spinning thread's dispatch blocks until the led callback ends."""
    executor = _parked()
    inside, release = threading.Event(), threading.Event()
    overlap = []
    running = []

    def slow():
        running.append(1)
        inside.set()
        release.wait(5)
        running.pop()

    def quick():
        overlap.append(bool(running))

    leader = threading.Thread(target=executor._lead, args=(_Work(slow),))
    leader.start()
    assert inside.wait(5)
    executor._idle = False    # the spinning thread woke with work of its own
    spinner = threading.Thread(target=executor._dispatch, args=(_Work(quick),))
    spinner.start()
    time.sleep(0.05)
    assert overlap == []      # still waiting for the token
    release.set()
    leader.join(5)
    spinner.join(5)
    assert overlap == [False]


def test_a_second_arrival_does_not_lead_while_a_leader_runs():
    executor = _parked()
    inside, release = threading.Event(), threading.Event()
    leader = threading.Thread(target=executor._lead, args=(_Work(lambda: (inside.set(), release.wait(5))),))
    leader.start()
    try:
        assert inside.wait(5)
        assert not executor._lead(_Work())   # the caller hands it off instead
    finally:
        release.set()
        leader.join(5)


def test_led_work_keeps_its_callback_group():
    """A busy mutually exclusive group: the led work waits in the group's backlog and is queued
    when the group is left, as the spinning thread's own work would."""
    executor, group = _parked(), MutuallyExclusiveCallbackGroup()
    work = _Work(group=group)
    assert group.try_enter()
    assert executor._lead(work)
    assert work.threads == []
    group.leave()
    executor._release_backlog(group)
    assert executor._queue.get_nowait() is work


def test_an_exception_in_a_led_callback_is_raised_by_the_spin():
    executor = _parked()

    def fails():
        raise ValueError('led')
    assert executor._lead(_Work(fails))
    assert executor._stop_waiting()   # the parked wait ends at the wake-up
    with pytest.raises(ValueError, match='led'):
        executor._spin_once(0)


def test_a_spin_nested_in_a_led_callback_runs_on_that_thread():
    """A callback run by a leader may spin the executor again (spin_once, or
    spin_until_future_complete), as it may on the spinning thread."""
    executor = _parked()
    inner = _Work()
    executor._enqueue(inner)
    outer = _Work(lambda: executor.spin_once(timeout_sec=1))
    assert executor._lead(outer)
    assert inner.threads == outer.threads == [threading.get_ident()]


def test_zros_callback_thread_spin_turns_leading_off(monkeypatch):
    monkeypatch.setattr(executors, '_LEADING_ALLOWED', False)
    executor = SingleThreadedExecutor(context=_Context())
    with executor._led():
        assert not executor._leading


def test_spin_once_is_never_led():
    executor = SingleThreadedExecutor(context=_Context())
    seen = []
    executor._enqueue(_Work(lambda: seen.append(executor._leading)))
    executor.spin_once(timeout_sec=1)
    assert seen == [False]


class _Pacing:
    """Only the lead-pausing state of a Subscription, to run `_note_led` on."""

    _note_led = Subscription._note_led

    def __init__(self) -> None:
        self._lead_skip = self._lead_pause = 0
        self._lead_slow = False


def test_two_slow_led_callbacks_in_a_row_pause_leading_and_each_pause_doubles():
    sub, slow, quick = _Pacing(), 2 * _LEAD_QUICK_S, _LEAD_QUICK_S / 10
    sub._note_led(slow)
    assert sub._lead_skip == 0         # one alone: most often a wait for the interpreter lock
    sub._note_led(slow)
    assert sub._lead_skip == _LEAD_PAUSE
    sub._lead_skip = 0
    sub._note_led(slow)
    assert sub._lead_skip == 2 * _LEAD_PAUSE
    sub._lead_skip = 0
    sub._note_led(quick)
    sub._note_led(slow)
    assert (sub._lead_skip, sub._lead_pause) == (0, 0)   # a quick one starts afresh


class _Arrivals:
    """Only what `Subscription._on_sample` touches below a full queue: records whether each
    sample was led (run at once by a parked executor) or handed off (scheduled)."""

    _on_sample = Subscription._on_sample
    _lead_or_schedule = Subscription._lead_or_schedule
    _events = None
    _scheduled = False
    _depth = 1 << 30   # a queue that never fills

    def __init__(self) -> None:
        import collections
        import types
        self._queue = collections.deque()
        self._lead_skip = 0
        self._last_seen = 0.0
        self.ways: list[str] = []
        executor = types.SimpleNamespace(_leading=True, _lead=self._led)
        self._node = types.SimpleNamespace(_executor=executor)

    def _led(self, entity: object) -> bool:
        self.ways.append('led')
        self._queue.clear()
        return True

    def _schedule(self) -> None:
        self.ways.append('handed off')
        self._scheduled = True

    def drained(self) -> None:
        """The executor took everything and parked again."""
        self._queue.clear()
        self._scheduled = False


def test_a_burst_takes_the_hand_off_and_a_quiet_arrival_leads_again(monkeypatch):
    now = [1.0]
    monkeypatch.setattr(subscription, '_clock', lambda: now[0])
    sub, step = _Arrivals(), _BURST_GAP_S / 3
    sub._on_sample('first')            # after a quiet spell: led
    for _ in range(3):                 # then samples close behind each other
        now[0] += step
        sub._on_sample('burst')
    assert sub.ways == ['led', 'handed off']   # (the rest joined the queued one)
    sub.drained()
    now[0] += step
    sub._on_sample('still the burst')  # the executor emptied the queue, but the burst goes on
    assert sub.ways[-1] == 'handed off'
    sub.drained()
    now[0] += 10 * _BURST_GAP_S
    sub._on_sample('quiet again')
    assert sub.ways[-1] == 'led'


def test_leading_is_off_unless_asked_for_and_a_bad_setting_is_one_line():
    from zros.config import settings_from_env
    from zros.errors import ZrosError
    assert [executors._leading_allowed(v) for v in (None, '', 'spin', ' spin ', 'zenoh', ' zenoh ')] == [
        False, False, False, False, True, True]
    with pytest.raises(ZrosError, match="ZROS_CALLBACK_THREAD must be 'spin'"):
        settings_from_env({'ZROS_CALLBACK_THREAD': 'main'})
