"""How a subscription's queue is drained (zros.subscription): the executor takes a batch of
waiting samples in one turn of the take lock, yet delivers exactly what taking them one at a
time would, with KEEP_LAST and the `dropped` / `lost` counts unchanged. No Zenoh: samples are
stand-ins carrying real zros attachments, fed to `_on_sample` as Zenoh's thread feeds them."""
from __future__ import annotations

import functools
import threading
import types
from collections import deque

import pytest

from zros.subscription import _EVICTED_NOTES, Subscription, _Signal
from zros.wire import AttachmentWriter


class _Sample:
    """A numbered sample whose attachment offers `to_bytes()`, as zenoh-python's ZBytes does."""

    def __init__(self, number: int, attachment: bytes) -> None:
        self.number = number
        self.attachment = types.SimpleNamespace(to_bytes=functools.partial(bytes, attachment))


class _Writer:
    """One publisher: numbered samples with consecutive sequence numbers; `skip()` loses one
    on the way, as the network would."""

    def __init__(self) -> None:
        msg_type = types.SimpleNamespace(_HASH='00' * 4, _TYPE='test/Int')
        self._stamps = AttachmentWriter(msg_type)
        self._number = 0

    def sample(self) -> _Sample:
        self._number += 1
        return _Sample(self._number, self._stamps.next())

    def skip(self) -> None:
        self._number += 1
        self._stamps.next()


def _subscription(depth: int, on_message=None) -> Subscription:
    """A Subscription without a session: its queue, counters and delivery, with a callback that
    gets the sample's number (the decoding is not what these tests are about)."""
    sub = Subscription.__new__(Subscription)
    sub._queue = deque(maxlen=depth)
    sub._depth = depth
    sub._evicted = deque(maxlen=_EVICTED_NOTES)
    sub._take_lock = threading.Lock()
    sub._handing_off = sub._refilling = False
    sub._taken, sub._refilled = _Signal(), _Signal()
    sub._drops_noted = 0
    sub._last_seq = {}
    sub._pull_wanted = False
    sub.dropped = sub.lost = sub.received = 0
    sub._scheduled = False
    sub._plain = True
    sub._node = types.SimpleNamespace(_executor=None)
    sub.delivered = []

    def deliver(sample):
        sub.received += 1
        sub._note_gap(*_gid_seq(sample))
        sub.delivered.append(sample.number)
        return on_message(sample.number) if on_message else None
    sub._deliver_plain = deliver
    return sub


def _gid_seq(sample: _Sample) -> tuple[bytes, int]:
    from zros.wire import read_header
    gid, seq, _, _ = read_header(sample.attachment.to_bytes())
    return gid, seq


def test_a_batch_delivers_every_waiting_sample_in_order_within_its_budget():
    sub, writer = _subscription(10), _Writer()
    for _ in range(7):
        sub._on_sample(writer.sample())
    sub._execute(4)
    assert sub.delivered == [1, 2, 3, 4] and len(sub._queue) == 3
    assert sub._scheduled   # more is waiting: it stays in the executor's queue
    sub._execute(64)
    assert sub.delivered == [1, 2, 3, 4, 5, 6, 7]
    assert (sub.received, sub.dropped, sub.lost, sub._scheduled) == (7, 0, 0, False)


def test_spin_once_takes_one_sample_per_call():
    sub, writer = _subscription(10), _Writer()
    for _ in range(3):
        sub._on_sample(writer.sample())
    sub._execute()
    assert sub.delivered == [1] and len(sub._queue) == 2


def test_samples_of_a_batch_that_newer_arrivals_overtake_are_dropped_not_delivered():
    """Depth 3: the executor takes 1, 2, 3 in one batch; while 1's callback runs, 4, 5, 6
    arrive. One at a time, 2 and 3 would have been pushed out by them: so they are here."""
    writer = _Writer()

    def on_message(number):
        if number == 1:
            for _ in range(3):
                sub._on_sample(writer.sample())
    sub = _subscription(3, on_message)
    for _ in range(3):
        sub._on_sample(writer.sample())
    sub._execute(64)
    assert sub.delivered == [1] and sub.dropped == 2 and list(s.number for s in sub._queue) == [4, 5, 6]
    sub._execute(64)
    assert sub.delivered == [1, 4, 5, 6]
    assert (sub.received, sub.dropped, sub.lost) == (4, 2, 0)   # the depth rule's drops are not losses


def test_a_loss_among_overtaken_and_pushed_out_samples_still_counts_once():
    """The network loses 4; 2 and 3 are overtaken in the executor's batch and 5 is pushed out
    of the queue by Zenoh's thread: `lost` is 1 whichever way each sample went."""
    writer = _Writer()

    def on_message(number):
        if number == 1:
            writer.skip()                     # 4: lost on the way
            for _ in range(4):                # 5 .. 8: the queue of 3 pushes out 5
                sub._on_sample(writer.sample())
    sub = _subscription(3, on_message)
    for _ in range(3):
        sub._on_sample(writer.sample())
    sub._execute(64)
    sub._execute(64)
    assert sub.delivered == [1, 6, 7, 8]
    assert (sub.dropped, sub.lost) == (3, 1)


@pytest.mark.parametrize('ending', ['raises', 'returns a coroutine'])
def test_what_a_batch_leaves_when_its_callback_raises_or_is_async_waits_for_the_next_turn(ending):
    class Boom(Exception):
        pass

    async def later():
        return None

    def on_message(number):
        if number == 2:
            if ending == 'raises':
                raise Boom()
            return coroutine
    coroutine = later() if ending != 'raises' else None
    sub, writer = _subscription(10, on_message), _Writer()
    for _ in range(5):
        sub._on_sample(writer.sample())
    if ending == 'raises':
        with pytest.raises(Boom):
            sub._execute(64)
    else:
        assert sub._execute(64) is coroutine
        coroutine.close()
    assert [s.number for s in sub._queue] == [3, 4, 5] and sub._scheduled
    sub._execute(64)
    assert sub.delivered == [1, 2, 3, 4, 5] and (sub.dropped, sub.lost) == (0, 0)


def test_samples_put_back_behind_a_queue_that_filled_meanwhile_are_dropped_as_overtaken():
    class Boom(Exception):
        pass
    writer = _Writer()

    def on_message(number):
        if number == 1:
            for _ in range(3):   # the queue (depth 3) fills behind the batch's 2 and 3
                sub._on_sample(writer.sample())
            raise Boom()
    sub = _subscription(3, on_message)
    for _ in range(3):
        sub._on_sample(writer.sample())
    with pytest.raises(Boom):
        sub._execute(64)
    assert [s.number for s in sub._queue] == [4, 5, 6] and sub.dropped == 2
    sub._execute(64)
    assert sub.delivered == [1, 4, 5, 6] and sub.lost == 0


def _flooded(depth: int) -> tuple[Subscription, types.SimpleNamespace]:
    """A subscription of a spinning SingleThreadedExecutor (a stand-in: its queue of other work,
    where callbacks run) whose last batch Zenoh's thread had filled and waited on."""
    import queue
    sub = _subscription(depth)
    executor = types.SimpleNamespace(_queue=queue.SimpleQueue(), _runs_on_waiting_thread=True, _idle=False,
                                     _leading=False)
    sub._node = types.SimpleNamespace(_executor=executor)
    sub._scheduled = True
    return sub, executor


def test_under_a_flood_the_executor_waits_for_the_next_queueful_and_zenohs_thread_hands_it_over(monkeypatch):
    import time
    from zros import subscription
    monkeypatch.setattr(subscription, '_HAND_OFF_S', 10.0)   # (however loaded the machine)
    sub, _ = _flooded(3)
    writer = _Writer()
    refilled: list[bool] = []

    def spinning_thread():
        refilled.append(sub._await_refill(time.perf_counter() + 10.0))
        sub._execute(64)
    spinner = threading.Thread(target=spinning_thread)
    start = time.monotonic()
    spinner.start()
    while not sub._refilling and time.monotonic() - start < 5:
        time.sleep(0.001)
    for _ in range(4):   # the fourth finds the queue full: it waits until the executor took it
        sub._on_sample(writer.sample())
    spinner.join(10)
    assert refilled == [True] and time.monotonic() - start < 8   # woken by the full queue
    sub._execute(64)   # (the fourth, if it came after the executor's batch)
    assert sub.delivered == [1, 2, 3, 4] and (sub.dropped, sub.lost) == (0, 0)


def test_the_wait_for_a_refill_gives_way_to_other_work_and_to_its_deadline():
    import time
    sub, executor = _flooded(3)
    executor._queue.put('a timer, a service, another subscription')
    assert not sub._await_refill(time.perf_counter() + 5.0)   # at once: the other work goes first
    executor._queue.get()
    start = time.perf_counter()
    assert sub._await_refill(start + 0.05)   # nothing came: back after the deadline
    assert 0.04 < time.perf_counter() - start < 2.0
    assert not sub._await_refill(time.perf_counter() - 1)   # the turn's waiting time is spent
