"""Subscriptions: samples arrive on Zenoh's thread, wait undecoded in a bounded queue, and are
read, decoded and handed to the callback on the executor.

Zenoh's receiving thread puts each sample in the subscription's Zenoh channel (a FIFO of 256,
the size zenoh-python gives a callback's channel; when it is full, Zenoh's thread waits).
Two readers take from it, one at a time:

- The pump, a thread of the subscription's own (as zenoh-python runs a callback): one hand-off.
  It appends the sample, untouched, to the subscription's queue and puts the subscription in
  its executor's queue if it is not there yet: no copy, no parsing, so that it holds the GIL as
  little as possible. The exception is an executor parked in `spin()` with nothing to do and a
  sample that comes after a quiet spell (_BURST_GAP_S), when leading is on: then the pump runs
  the sample through the executor at once (zros.executors, leader/follower).
- The pull: an executor whose only subscription this is receives from the channel on the
  spinning thread itself while the pump steps aside (`_take_channel`), which saves the thread
  hop (zros.executors). It delivers straight from the channel while it keeps up; after a
  callback slower than _HAND_OFF_S it queues what waited, with the depth rule below, before
  delivering more (`_queue_pulled`), as the pump would have queued it meanwhile.

The queue is the QoS depth (KEEP_LAST): when full, the oldest sample is pushed out and counted in
`dropped`, so a sample the depth rule drops is never copied or decoded. spin() takes a batch of
waiting samples per turn (`_execute`) and applies the same rule to it before each delivery. The
executor reads each sample's attachment once. Gaps in a publisher's sequence numbers over every
sample that reached the subscription (pushed-out ones included: their attachments are kept for
this, up to _EVICTED_NOTES) are counted in `lost`; samples of the wrong type, larger than the
size limit (zros.wire.max_message_size, refused before they are copied) or that do not decode
strictly as the subscription's type are counted in `rejected` and logged once per publisher: a
malformed sample never reaches the callback. What the callback does with a well-formed message is
its own business: an exception it raises propagates out of spin(), as in rclpy, and the samples
still waiting are delivered by the next spin.
"""
from __future__ import annotations

import enum
import inspect
import queue as queues
import threading
import time
from collections import deque
from collections.abc import Iterable
from typing import TYPE_CHECKING, Any, Callable, Generic, Union

from zros.context import PUMP_THREAD_PREFIX
from zros.entity import QueuedEntity
from zros.errors import DecodeError
from zros.graph import EntityKind
from zros.message import MsgT, decoder
from zros.qos import DurabilityPolicy, QoSProfile
from zros.wire import (GID_AT, MAGIC, TYPE_AT, WAKE, WRITER_STAMP, foreign_protocol, is_wake,
                       max_message_size, mismatch_reason, read_header, type_tail)

if TYPE_CHECKING:
    from zros.node import Node

__all__ = ['Subscription', 'MessageInfo', 'SubscriptionCallback']

# How many publishers' rejected samples a subscription logs (one line each).
_MAX_REPORTED = 16
# How many pushed-out samples' attachments wait for the executor to read their sequence numbers.
_EVICTED_NOTES = 4096

MessageInfo = dict  # {'source_timestamp', 'received_timestamp', 'publication_sequence_number', ...}

#: What a subscription calls: with the message, or (two positional parameters) with the message
#: and its MessageInfo, as rclpy does.
SubscriptionCallback = Union[Callable[[MsgT], Any], Callable[[MsgT, MessageInfo], Any]]


class _Timed:
    """A sample with its arrival time, for a callback that takes MessageInfo."""

    __slots__ = ('sample', 'received')

    def __init__(self, sample: Any, received: int) -> None:
        self.sample, self.received = sample, received

    @property
    def attachment(self) -> Any:
        return self.sample.attachment


class _Signal:
    """A wake-up from one thread to the one waiting for it (Zenoh's thread and the executor
    hand a full queue back and forth under a flood, once per queueful): a C-level queue, since
    a wait and a signal cost 0.6 µs that way against 4 µs through threading.Event's Python.
    One thread waits (and clears); any thread signals."""

    __slots__ = ('_queue',)

    def __init__(self) -> None:
        self._queue: queues.SimpleQueue = queues.SimpleQueue()

    def set(self) -> None:
        self._queue.put(None)

    def clear(self) -> None:
        """Forget a signal given after the last wait had timed out."""
        waiting = self._queue
        while not waiting.empty():
            waiting.get_nowait()

    def wait(self, timeout: float) -> bool:
        try:
            self._queue.get(timeout=timeout)
        except queues.Empty:
            return False
        return True


class CallbackType(enum.Enum):
    """How a subscription calls its callback (rclpy's Subscription.CallbackType)."""

    MessageOnly = 0
    WithMessageInfo = 1


def _callback_type(callback: Callable) -> CallbackType:
    """As rclpy decides: `callback(msg)` if it can be called with one argument, else
    `callback(msg, info)` if with two.

    Raises:
        RuntimeError: it can be called with neither.
    """
    try:
        signature = inspect.signature(callback)
    except (TypeError, ValueError):   # a builtin without a signature: called with the message
        return CallbackType.MessageOnly
    for arguments, kind in (((None,), CallbackType.MessageOnly), ((None, None), CallbackType.WithMessageInfo)):
        try:
            signature.bind(*arguments)
            return kind
        except TypeError:
            continue
    raise RuntimeError(f'subscription callback {callback!r} must take the message, or the message and '
                       'its MessageInfo')


# How many samples wait in a subscription's Zenoh channel before Zenoh's receiving thread waits
# for them to be taken: zenoh-python's own default for a callback's channel (DefaultHandler),
# which zros used before it read the channel itself.
_CHANNEL_CAPACITY = 256
# How long an executor waits for a subscription's pump to step aside (`_take_channel`).
_TAKE_CHANNEL_S = 1.0
# Bumped whenever a node gains or loses a subscription (zros.node): an executor receives from a
# subscription's channel itself (the pull) only while its set of subscriptions stays the same.
_subscription_lists_version = 0


def subscription_lists_version() -> int:
    """A counter that changes whenever any node gains or loses a subscription."""
    return _subscription_lists_version


def subscription_lists_changed() -> None:
    """Note that some node gained or lost a subscription."""
    global _subscription_lists_version
    _subscription_lists_version += 1


# How long Zenoh's thread waits for an idle executor to take a full KEEP_LAST queue.
_HAND_OFF_S = 0.002
# How long, at most per turn, spin() waits for a KEEP_LAST queue it emptied under a flood (Zenoh's
# thread had filled it and waited) to fill again, instead of parking on its own queue.
_REFILL_S = 0.0005
# Two callbacks in a row led on Zenoh's thread (zros.executors) that take longer than this make
# the next _LEAD_PAUSE samples (doubling up to _LEAD_PAUSE_MAX) take the hand-off instead.
_LEAD_QUICK_S = 0.001
_LEAD_PAUSE, _LEAD_PAUSE_MAX = 64, 65536
_clock = time.perf_counter
# A sample that arrives sooner than this after the subscription's previous one (or after the end
# of the callback its thread led) is part of a burst: it takes the hand-off, so that Zenoh's
# thread receives the next sample while the executor runs this one. Longer than Zenoh's
# thread's own work per sample under a flood (a few µs), shorter than a round trip (about 80 µs).
_BURST_GAP_S = 30e-6


class Subscription(QueuedEntity, Generic[MsgT]):
    """Receives messages of one type on one topic; made by `Node.create_subscription`.

    Samples are queued on Zenoh's thread and decoded and handed to the callback on the node's
    executor (see the module docstring). Generic in the message type, so that an editor
    checks the callback's argument against it. `destroy()` or `Node.destroy_subscription`
    undeclares its Zenoh subscriber and graph token.
    """

    _events: Any = None  # zros.event_handler's tracker, when a deadline or message-lost event needs it
    CallbackType = CallbackType

    def __init__(self, node: 'Node', msg_type: type[MsgT], topic: str, callback: SubscriptionCallback[MsgT],
                 qos: QoSProfile, callback_group: Any, raw: bool = False) -> None:
        import zenoh
        import zenoh.ext
        from zros.keys import topic_key
        self._node = node  # the Zenoh callback may run before NodeEntity.__init__ below
        self.msg_type: Any = msg_type   # a class built at run time: its _TYPE is not declared
        self.topic_name = topic
        self.callback: Callable[..., Any] = callback
        self.qos_profile = qos
        self.callback_group = callback_group
        self.raw = raw
        self._callback_type = _callback_type(callback)
        self._with_info = self._callback_type is CallbackType.WithMessageInfo
        self._plain = not raw and not self._with_info   # the callback takes the message only
        self._queue: deque = deque(maxlen=qos.queue_depth)  # Zenoh samples, undecoded
        self._depth: int = qos.queue_depth                   # its maxlen (the one read everywhere)
        self._evicted: deque = deque(maxlen=_EVICTED_NOTES)  # attachments of pushed-out samples
        self._take_lock = threading.Lock()   # the executor's take vs. a push-out
        self._taken = _Signal()       # _hand_off: the executor took from the queue
        self._handing_off = False
        self._refilled = _Signal()    # _await_refill: the queue is full again
        self._refilling = False
        self._lead_skip = self._lead_pause = 0   # _note_led
        self._lead_slow = False
        self._last_seen = 0.0   # _on_sample: when the last sample came, or a led callback ended
        self._drops_noted = 0
        self._tail = type_tail(msg_type)
        self._decode = decoder(msg_type)
        self._max_size = max_message_size()
        self._last_seq: dict[bytes, int] = {}
        self._complained: set[bytes] = set()
        self.dropped = 0
        self.lost = 0
        self.rejected = 0
        self.received = 0
        self._session = session = node.context.session
        self._key = key = topic_key(node.context.domain_id, topic)
        self._session_local = zenoh.Locality.SESSION_LOCAL   # (`_poke`)
        # The pull (zros.executors): an executor with this as its only subscription receives
        # from the channel itself while its pump steps aside (`_take_channel`).
        self._pull_wanted = False
        self._pump_parked = threading.Event()
        self._resume = threading.Event()
        self._pullable = qos.durability != DurabilityPolicy.TRANSIENT_LOCAL
        self._last_pull = 0.0   # _queue_pulled: when the executor last took from the channel
        self._absent = False    # ... and whether a slow callback kept it away since
        if not self._pullable:
            self._zenoh = zenoh.ext.declare_advanced_subscriber(
                session, key, self._on_sample_timed if self._with_info else self._on_sample,
                history=zenoh.ext.HistoryConfig(detect_late_publishers=True, max_samples=max(1, qos.queue_depth)),
                subscriber_detection=True)
        else:
            self._zenoh = session.declare_subscriber(key, zenoh.handlers.FifoChannel(_CHANNEL_CAPACITY))
        super().__init__(node, EntityKind.SUBSCRIPTION, topic, msg_type, qos)
        if self._pullable:
            # Not a daemon thread, as zenoh-python's are not: the interpreter joins it before it
            # finalizes (it ends when the session closes), since a thread that comes back from
            # Zenoh for the interpreter lock once the interpreter is finalizing aborts the process.
            threading.Thread(target=self._pump, name=f'{PUMP_THREAD_PREFIX}{topic}').start()

    def get_publisher_count(self) -> int:
        """Count the publishers on this subscription's topic that the graph knows of now
        (from their liveliness tokens, so a brand-new one may be missing for a moment).

        :return: The number of publishers, local and remote.
        """
        return self._node.count_publishers(self.topic_name)

    # The pump: Zenoh's side of the hand-off, on a thread of the subscription's own, as
    # zenoh-python runs a callback (one thread per subscriber, blocking on its channel).
    def _pump(self) -> None:
        """Receive from the Zenoh channel until it closes (the subscription destroyed, the
        session closed) and hand each sample on (`_on_sample`); step aside while an executor
        receives from the channel itself (`_take_channel`). After a blocking receive, what
        else waits is taken without one (no interpreter lock given up and taken back per
        sample under a flood)."""
        receive, take = self._zenoh.recv, self._zenoh.try_recv
        on_sample = self._on_sample_timed if self._with_info else self._on_sample
        while True:
            try:
                sample = receive()
            except Exception:   # noqa: BLE001 - zenoh.ZError: the channel is closed
                return
            while sample is not None:
                try:
                    if self._pull_wanted:
                        if not is_wake(sample):
                            on_sample(sample)
                        self._pump_parked.set()
                        self._resume.wait()
                        break
                    on_sample(sample)
                except Exception as exc:  # noqa: BLE001 - as zenoh-python logs a callback's error
                    self._node.get_logger().error(f"subscription '{self.topic_name}': {exc!r}")
                try:
                    sample = take()
                except Exception:   # noqa: BLE001 - zenoh.ZError: the channel is closed
                    return

    def _take_channel(self) -> bool:
        """Executor thread, starting the pull: make the pump step aside (it finishes the sample
        in hand, then parks), and say whether it did within _TAKE_CHANNEL_S. Samples it handed
        on before parking wait in the queue, older than any left in the channel."""
        self._resume.clear()
        self._pump_parked.clear()
        self._pull_wanted = True
        self._poke()
        if self._pump_parked.wait(_TAKE_CHANNEL_S):
            return True
        self._give_channel()
        return False

    def _give_channel(self) -> None:
        """Executor thread, ending the pull: the pump receives again."""
        self._pull_wanted = False
        self._resume.set()

    def _poke(self) -> None:
        """Make whoever blocks on the channel (the pump, or a pulling executor) return: a wake-up
        sample (zros.wire.WAKE) put on the topic's key, delivered only inside this session."""
        try:
            self._session.delete(self._key, attachment=WAKE, allowed_destination=self._session_local)
        except Exception:  # noqa: BLE001 - zenoh.ZError: the session is closing, the waiter with it
            pass

    def _queue_pulled(self, sample: Any, budget: int) -> None:
        """Executor thread, pulling: queue `sample`, just taken from the channel (None: none),
        and what else waits there, as the pump would have queued them. How much: up to
        `budget`, and for KEEP_LAST at most the depth while the executor keeps up (it was last
        at the channel under _HAND_OFF_S ago: the rest waits in the channel, and Zenoh's thread
        with it, as the pump's hand-off waited for an idle executor), but everything after a
        longer absence (a slow callback), the older samples pushed out and counted as the pump
        would have pushed them out."""
        now = _clock()
        depth = self._depth
        if self._absent or now - self._last_pull > _HAND_OFF_S:
            self._absent = False
            budget = _CHANNEL_CAPACITY
        elif depth < budget:
            budget = depth
        self._last_pull = now
        queue, timed, events = self._queue, self._with_info, self._events
        receive = self._zenoh.try_recv
        if sample is None:
            sample = receive()
        while sample is not None:
            if timed:
                sample = _Timed(sample, time.time_ns())
            if len(queue) == depth and is_wake(sample):
                pass   # (a wake-up caught in a flood takes no message's place)
            else:
                if len(queue) == depth:
                    self._push_out()
                queue.append(sample)
                if events is not None:
                    events.on_sample()
            budget -= 1
            if budget <= 0:
                return
            try:
                sample = receive()
            except Exception:  # noqa: BLE001 - closed: what was queued is still delivered
                return

    def _release(self) -> None:
        super()._release()
        self._resume.set()   # a parked pump sees the closed channel and ends

    # Zenoh thread: queue the sample untouched (no copy, no parsing), then either run it here at
    # once, if it came after a quiet spell and the executor is parked and lets this thread lead
    # (zros.executors), or make sure the executor will run us. Without leading (the default) no
    # clock is read: a sample costs this thread a length check, an append and a flag test.
    def _on_sample(self, sample: Any) -> None:
        queue = self._queue
        if len(queue) == self._depth:
            if self._scheduled:
                self._hand_off()
            if len(queue) == self._depth:
                self._push_out()
        queue.append(sample)
        if self._events is not None:
            self._events.on_sample()
        executor = self._node._executor
        if executor is not None and executor._leading:
            self._lead_or_schedule(executor)
        elif not self._scheduled:
            self._schedule()

    def _lead_or_schedule(self, executor: Any) -> None:
        """`_on_sample` while the executor may be led: a sample after a quiet spell runs here,
        one close behind the previous (a burst) takes the hand-off."""
        now = _clock()
        burst = now - self._last_seen < _BURST_GAP_S
        self._last_seen = now
        if self._scheduled:
            return
        if burst:
            self._schedule()
        elif self._lead_skip:
            self._lead_skip -= 1
            self._schedule()
        elif not executor._lead(self):
            self._schedule()

    def _note_led(self, seconds: float) -> None:
        """After a callback this thread led: slow ones hold Zenoh's thread (its channel fills,
        and then reliable publishers wait for this callback, where a KEEP_LAST queue would
        drop instead), so after two slow ones in a row the next samples take the hand-off;
        each pause doubles the last. (One slow one alone is most often this thread waiting for
        the interpreter lock while another thread had it.)"""
        if seconds <= _LEAD_QUICK_S:
            self._lead_slow = False
            self._lead_pause = 0
        elif not self._lead_slow:
            self._lead_slow = True
        else:
            self._lead_pause = min(2 * self._lead_pause or _LEAD_PAUSE, _LEAD_PAUSE_MAX)
            self._lead_skip = self._lead_pause

    def _on_sample_timed(self, sample: Any) -> None:
        """`_on_sample` for a callback that takes MessageInfo: the arrival time goes along."""
        self._on_sample(_Timed(sample, time.time_ns()))

    def _hand_off(self) -> None:
        """A full queue whose executor is idle, woken for this queue, or waiting for it to fill
        (`_await_refill`): let it take the queue before pushing anything out. Under a flood this
        thread would otherwise keep the interpreter lock, and the executor would get it back
        only after the switch interval (5 ms): a depth-10 queue delivered 10 messages per 5 ms
        and dropped the rest. Waiting here (at most _HAND_OFF_S) gives it the lock at once; a
        busy executor is not waited for."""
        if self._refilling:
            self._taken.clear()
            self._handing_off = True
            self._refilled.set()
            self._taken.wait(_HAND_OFF_S)
            self._handing_off = False
            return
        executor = self._node._executor
        if executor is None or not executor._idle or not executor._runs_on_waiting_thread:
            return
        group = self.callback_group
        if group is not None and not group.can_execute(self):
            return
        self._taken.clear()
        self._handing_off = True
        if len(self._queue) == self._depth:
            self._taken.wait(_HAND_OFF_S)
        self._handing_off = False

    def _push_out(self) -> None:
        """KEEP_LAST: drop the oldest waiting sample, counted in `dropped`; its attachment is
        kept, unread, so that the executor can still count a gap before it in `lost`."""
        with self._take_lock:
            queue = self._queue
            if len(queue) == self._depth:
                self._evicted.append(queue.popleft().attachment)
                self.dropped += 1

    # Executor thread. spin_once takes one sample per call, as rclpy takes one message per
    # callback; spin() lets a subscription run up to `budget` waiting samples in one go.
    def _execute(self, budget: int = 1) -> Any:
        """Take up to `budget` waiting samples under one turn of the take lock and deliver them
        in order. KEEP_LAST still holds for the samples taken: before each delivery after the
        first, those of them that `depth` newer samples have overtaken meanwhile (Zenoh's thread kept appending
        while a callback ran) are dropped, counted in `dropped` as a push-out would count them,
        so a batch never delivers a sample that one-at-a-time taking would have pushed out.
        What a raising callback or an `async def` one leaves untaken goes back to the front of
        the queue, by the same rule. A batch Zenoh's thread was waiting on (a flood into a full
        KEEP_LAST queue) is followed, while the budget lasts, by the next one (`_await_refill`).
        While the executor pulls (zros.executors), samples that came during a slow callback
        wait in the channel, not in the queue: they are queued before the next delivery
        (`_queue_pulled`), so that they overtake the batch as they would have."""
        queue = self._queue
        deliver = self._deliver_plain if self._plain else self._deliver
        depth = self._depth
        pulled = self._pull_wanted
        taken: list = []
        index = count = 0
        deadline = None
        try:
            while budget > 0:
                with self._take_lock:   # pushed-out samples are older than the ones taken here
                    notes = self._take_notes() if self._evicted else None
                    taken = [queue.popleft() for _ in range(min(budget, len(queue)))]
                flood = self._handing_off
                if flood:
                    self._handing_off = False
                    self._taken.set()
                if notes:
                    self._count_notes(notes)
                count, index = len(taken), 0
                budget -= count
                while index < count:
                    # (the first was taken at the lock turn, as one-at-a-time would take it; each
                    # later one is taken now, after what arrived during the callbacks before it)
                    overtaken = count - index + len(queue) - depth if index else 0
                    if overtaken > 0:
                        self._drop_taken(taken[index:index + overtaken])
                        index += overtaken
                        continue
                    item = taken[index]
                    index += 1
                    if pulled:
                        start = _clock()
                        pending = deliver(item)
                        if _clock() - start > _HAND_OFF_S:   # (see the docstring)
                            self._absent = True
                            self._queue_pulled(None, _CHANNEL_CAPACITY)
                    else:
                        pending = deliver(item)
                    if pending is not None:
                        return pending   # an async callback's coroutine: it runs as a task first
                if not flood or budget <= 0:
                    return None
                if deadline is None:
                    deadline = _clock() + _REFILL_S
                if not self._await_refill(deadline):
                    return None
            return None
        finally:
            if index < count:
                self._put_back(taken[index:])
            self._rearm()   # also after a callback raised: what is waiting (and what comes) still runs

    def _await_refill(self, deadline: float) -> bool:
        """Executor thread, having emptied a queue Zenoh's thread had filled and waited on: wait
        (until `deadline`) for it to fill again, and say whether to take more. Parking on the
        executor's queue instead costs two wake-ups per queueful (the executor's, then, once the
        queue is full, Zenoh's hand-off), the floor of a depth-10 flood; waiting here costs one,
        and Zenoh's thread never wakes a parked executor meanwhile. Only on the thread that
        spins, and only while no other work is queued for it: timers and other entities wait
        at most _REFILL_S per turn."""
        executor = self._node._executor
        if executor is None or not executor._runs_on_waiting_thread or not executor._queue.empty():
            return False
        remaining = deadline - _clock()
        if remaining <= 0:
            return False
        self._refilled.clear()
        self._refilling = True
        if len(self._queue) < self._depth:
            self._refilled.wait(remaining)
        self._refilling = False
        return True

    def _drop_taken(self, samples: list) -> None:
        """Executor thread: KEEP_LAST for samples it took and newer ones overtook. Counted as
        Zenoh's thread counts a push-out (under the take lock, since both threads add to
        `dropped`), and their gaps counted in `lost` at once: they are older than anything
        still waiting or noted."""
        with self._take_lock:
            self.dropped += len(samples)
            self._drops_noted += len(samples)
        self._count_notes([getattr(sample, 'attachment', None) for sample in samples])

    def _put_back(self, samples: list) -> None:
        """Samples taken but not delivered (a callback raised, or returned a coroutine) go back
        to the front of the queue, oldest first in line; those that no longer fit are older
        than all that waits there, so KEEP_LAST drops them."""
        with self._take_lock:
            queue = self._queue
            late = []
            for sample in reversed(samples):
                if len(queue) < self._depth:
                    queue.appendleft(sample)
                else:
                    late.append(sample)
        if late:
            late.reverse()
            self._drop_taken(late)

    def _take_notes(self) -> deque:
        """Under `_take_lock`: the attachments of the samples pushed out so far."""
        notes, self._evicted = self._evicted, deque(maxlen=_EVICTED_NOTES)
        if self.dropped - self._drops_noted > len(notes):
            # More were pushed out than notes kept (the executor was away): a gap over them is
            # not a loss, so the writers' sequences start afresh.
            self._last_seq.clear()
        self._drops_noted = self.dropped
        return notes

    def _count_notes(self, notes: Iterable[Any]) -> None:
        lost = self.lost
        for attachment in notes:
            header = read_header(attachment.to_bytes()) if attachment is not None else None
            if header is not None:
                self._count_gap(header[0], header[1])
        if lost != self.lost and self._events is not None:
            self._events.on_sample()  # report the gap now, not at the next arrival

    def _count_gap(self, gid: bytes, seq: int) -> None:
        """`lost`: gaps in each writer's sequence numbers, over every sample that reached this
        subscription (delivered or pushed out), in arrival order."""
        last = self._last_seq.get(gid)
        if last is None or seq > last:
            if last is not None and seq > last + 1:
                self.lost += seq - last - 1
            self._last_seq[gid] = seq

    def _note_gap(self, gid: bytes, seq: int) -> None:
        """`_count_gap` for the sample being delivered; a new loss is reported at once."""
        lost = self.lost
        self._count_gap(gid, seq)
        if lost != self.lost and self._events is not None:
            self._events.on_sample()

    def _deliver_plain(self, sample: Any) -> Any:
        """`_deliver` for a callback that takes the message only. The common case (a zros writer
        of this type, a payload within the limit) reads the attachment in place (two slice
        compares, one struct read); any other sample takes `_deliver`."""
        attachment = sample.attachment
        payload = sample.payload
        if attachment is None or len(payload) > self._max_size:
            return self._deliver(sample)
        attachment = attachment.to_bytes()
        if attachment[TYPE_AT:] != self._tail or attachment[:GID_AT] != MAGIC:
            return self._deliver(sample)
        self.received += 1
        gid, seq, _ = WRITER_STAMP.unpack_from(attachment, GID_AT)
        last_seq = self._last_seq
        last = last_seq.get(gid)
        if last is None or seq == last + 1:
            last_seq[gid] = seq
        else:
            self._note_gap(gid, seq)
        try:
            msg = self._decode(payload.to_bytes())
        except DecodeError as exc:
            self._reject(gid, str(exc))
            return None
        return self.callback(msg)

    def _deliver(self, item: Any) -> Any:
        """Check, decode and hand one sample to the callback, whatever its sender and whatever
        the callback takes (MessageInfo, raw bytes)."""
        if self._with_info:
            sample, received = item.sample, item.received
        else:
            sample, received = item, 0
        if is_wake(sample):
            return None   # an executor's wake-up for another subscription of this key (the pull)
        self.received += 1
        attachment = sample.attachment
        checked = self._check_sender(attachment.to_bytes() if attachment is not None else b'')
        if checked is None:
            return None
        gid, seq, source_ns = checked
        payload = sample.payload
        if len(payload) > self._max_size:  # refused before it is copied or decoded
            self._reject(gid, f'a message of {len(payload)} bytes is larger than the limit of '
                              f'{self._max_size} bytes (ZROS_MAX_MESSAGE_SIZE)')
            return None
        if self.raw:
            msg = payload.to_bytes()
        else:
            try:
                msg = self._decode(payload.to_bytes())
            except DecodeError as exc:
                self._reject(gid, str(exc))
                return None
        if self._with_info:
            return self.callback(msg, {'source_timestamp': source_ns, 'received_timestamp': received,
                                       'publication_sequence_number': seq,
                                       'reception_sequence_number': self.received})
        return self.callback(msg)

    def _check_sender(self, attachment: bytes) -> tuple[bytes, int, int] | None:
        """(gid, sequence, source time) of a sample that is not the common case: another type
        (rejected), another protocol version (rejected), or no zros attachment (a plain Zenoh
        client: decoded strictly as this type). None when it is rejected."""
        header = read_header(attachment)
        if header is not None:
            gid, seq, source_ns, tail = header
            self._note_gap(gid, seq)
            if tail != self._tail:
                self._reject(gid, mismatch_reason(tail, self.msg_type, 'a publisher'))
                return None
            return gid, seq, source_ns
        old = foreign_protocol(attachment)
        if old is not None:
            self._reject(b'', old)
            return None
        return b'', 0, 0

    def _reject(self, gid: bytes, reason: str) -> None:
        """Count a refused sample; log the first one of each publisher (senders without a zros
        attachment are one publisher, b''), and stop logging after _MAX_REPORTED of them so
        that forged publisher ids cannot flood the log."""
        self.rejected += 1
        if gid in self._complained or len(self._complained) > _MAX_REPORTED:
            return
        self._complained.add(gid)
        if len(self._complained) > _MAX_REPORTED:
            reason = f'{reason}; more publishers send bad samples: they are counted, not logged'
        self._node.get_logger().error(
            f"dropping messages on '{self.topic_name}': {reason} (reported once per publisher)")
