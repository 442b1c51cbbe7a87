"""Pub/sub benchmark: zros against raw zenoh-python, same run, same machine (docs/architecture.md §8).

    python benchmarks/pubsub.py            # full run, about a minute
    python benchmarks/pubsub.py --quick    # smaller counts, one run each, no 8 MB case
    python benchmarks/pubsub.py --only latency:twist,throughput:twist --rounds 4 --json out.json
    python benchmarks/pubsub.py --node     # also the user's path, and latency:busy

What is measured, for both libraries, in alternating runs (raw, zros, zros, raw, ...) so that
drifting machine load hits both alike:
- round-trip latency, ping-pong between two processes: a `geometry_msgs/msg/Twist` and a
  1 MB `sensor_msgs/msg/Image` (rgb8); median, p90 and p99 after a warm-up. The echo side
  decodes each message and publishes it back; the pinging side sends the next ping from the
  callback that received the pong;
- throughput: one process publishes as fast as it can (reliable, CongestionControl.BLOCK),
  the other counts what its callback receives over a fixed window; msg/s, MB/s and losses
  (Twist at depth 10 and KEEP_ALL; 64 KiB, 1 MB, 8 MB and 32 MB images, the large ones with
  and without shared memory);
- the copies of a large payload between publish() and the callback, stage by stage, in one
  process: zros's path against the old protocol v1 path (msgpack map with the pixels inline);
- with --node, the user's path (issue 35): each case also through Node subclasses spun by
  `zros.spin(node)`, on the main thread (echo, flood) or a thread of their own (ping, count),
  as the ROS 2 tutorials write them; and `latency:busy`, that round trip while a second node
  of the pinging process, on an executor of its own, runs a 50 ms callback 15 times a second.

"Raw" is what a careful user of zenoh-python writes: the message's fields by hand in a msgpack
array (the pixels inline as `bin`), `declare_publisher` with the options zros uses for a
RELIABLE publisher, `declare_subscriber` with a callback that decodes the payload on
zenoh-python's callback thread. "zros" is the rclpy-style API: `Node.create_publisher` /
`create_subscription` (QoS depth 10: RELIABLE, KEEP_LAST 10) and a spinning
`SingleThreadedExecutor`; the small-message throughput is also measured with a KEEP_ALL
subscription: at depth 10 a subscriber that cannot keep up drops by the QoS rule, and what it
delivers should match KEEP_ALL. "dds" is cyclonedds-python (PyPI `cyclonedds`, what ROS 2's
default middleware is built on) with the same message as an IDL struct, reliable, keep-last
10, over loopback unicast; its columns are left out when the package is not installed.
Shared memory: both sides run with `ZROS_SHM_POOL_SIZE` (the `:noshm` cases set it to 0, so
the payload crosses loopback TCP), raw included, as `zros.config.open_session` applies it.

Every run uses two fresh worker processes started by this script: the measuring side first,
so it becomes the loopback hub, then its peer. Both open their session with
`zros.config.open_session`, so raw and zros get identical transport settings (peer mode,
listening on tcp/127.0.0.1:0, multicast scouting off, the domain's hub on loopback). Each run
takes the first domain id from 201 up whose hub port is free, so nothing else joins. Workers
report JSON lines on stdout and clean up (undeclare, close the session / zros.shutdown) when
their stdin closes; the peer always goes first, and workers are killed on any error.
"""
from __future__ import annotations

import argparse
import json
import math
import os
import platform
import queue
import signal
import struct
import subprocess
import sys
import threading
import time
import types
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable

REPO = Path(__file__).resolve().parents[1]
if str(REPO) not in sys.path:
    sys.path.insert(0, str(REPO))

#: First domain id tried; a case moves up while a hub port is taken (or in TIME_WAIT).
DOMAIN_BASE = 201
#: A worker that lives longer than this kills itself (the orchestrator is gone or stuck).
WORKER_WATCHDOG_S = 90.0
#: How long a worker may take to start (a loaded machine: load 20 on 2 CPUs took over 15 s).
READY_S = 45.0

PING_TOPIC, PONG_TOPIC, FLOOD_TOPIC = '/zros_bench/ping', '/zros_bench/pong', '/zros_bench/flood'

# Image sizes: rgb8 rows of `width` pixels, enough rows for the nominal size. A case name may end
# in ':noshm' (the same message with shared memory off on both sides).
SIZES = {
    'twist': None,
    '64KB': (128, 171),    # 65,664 bytes of pixels
    '1MB': (1024, 342),    # 1,050,624 bytes of pixels
    '8MB': (2048, 1366),   # 8,392,704 bytes of pixels
    '32MB': (4096, 2731),  # 33,558,528 bytes of pixels
}
#: The shared-memory pool of the benchmark processes: a 32 MB message needs room to be in flight.
SHM_POOL = '256M'

# docs/architecture.md §8 / issue targets: (kind, bound); 'max' = zros/raw at most bound, 'min' = at least;
# 'abs' = zros msg/s at least bound.
LATENCY_TARGET = ('max', 1.2)     # small-message latency within 1.2x of raw
LARGE_LATENCY_TARGET = ('max', 1.11)  # 90% of raw bandwidth = round trip at most 1/0.9 of raw
SMALL_RATE_TARGET = ('min', 0.80)     # KEEP_ALL Twist throughput
DEPTH10_TARGET = ('min', 0.90)        # delivered at depth 10 against delivered at KEEP_ALL
RATE_TARGETS = {'1MB': ('min', 0.90), '8MB': ('abs', 400.0)}


def size_of(case: str) -> tuple[int, int] | None:
    return SIZES[case.split(':')[0]]


# ================================================================================ payloads
def pixels(case: str) -> bytes:
    width, height = size_of(case)
    size = width * height * 3
    return (bytes(range(256)) * (size // 256 + 1))[:size]


def raw_wire(case: str) -> list:
    """The benchmark message's fields, by hand: what a raw user sends (pixels inline as bin)."""
    if case == 'twist':
        return [[0.0, 0.5, 0.0], [0.0, 0.0, 0.25]]
    width, height = size_of(case)
    return [[[0, 0], 'camera'], height, width, 'rgb8', 0, width * 3, pixels(case)]


def raw_set_seq(case: str, wire: list, seq: int) -> None:
    if case == 'twist':
        wire[0][0] = float(seq)
    else:
        wire[0][0][0] = seq


def raw_get_seq(case: str, wire: list) -> int:
    return int(wire[0][0]) if case == 'twist' else wire[0][0][0]


def zros_msg(case: str) -> Any:
    """The same message as `raw_wire(case)`, as a zros message object."""
    import numpy as np
    from interfaces.geometry_msgs.msg import Twist
    from interfaces.sensor_msgs.msg import Image
    if case == 'twist':
        msg = Twist()
        msg.linear.y, msg.angular.z = 0.5, 0.25
        return msg
    width, height = size_of(case)
    msg = Image(height=height, width=width, encoding='rgb8', step=width * 3,
                data=np.frombuffer(pixels(case), dtype=np.uint8))
    msg.header.frame_id = 'camera'
    return msg


def zros_set_seq(case: str, msg: Any, seq: int) -> None:
    if case == 'twist':
        msg.linear.x = float(seq)
    else:
        msg.header.stamp.sec = seq


def zros_get_seq(case: str, msg: Any) -> int:
    return int(msg.linear.x) if case == 'twist' else msg.header.stamp.sec


def message_case(case: str) -> str:
    """The message a case sends: `busy` is the Twist round trip beside a slow neighbour."""
    return 'twist' if case == 'busy' else case


def zros_type(case: str) -> type:
    from interfaces.geometry_msgs.msg import Twist
    from interfaces.sensor_msgs.msg import Image
    return Twist if case == 'twist' else Image


# ================================================================================ workers
def emit(event: str, **fields: Any) -> None:
    """One JSON line to the orchestrator."""
    sys.stdout.write(json.dumps({'event': event, **fields}) + '\n')
    sys.stdout.flush()


def watch_stdin() -> threading.Event:
    """Set when the orchestrator closes our stdin: time to clean up and exit."""
    stop = threading.Event()

    def watch() -> None:
        for _ in sys.stdin:
            pass
        stop.set()
    threading.Thread(target=watch, daemon=True, name='bench-stdin').start()
    return stop


def start_watchdog() -> None:
    """A worker must never outlive a stuck or dead orchestrator (nor hang at exit)."""
    timer = threading.Timer(WORKER_WATCHDOG_S, lambda: os._exit(3))
    timer.daemon = True
    timer.start()


class RawSide:
    """A zenoh session opened exactly as zros opens its own (`zros.config.open_session`), with
    the publisher options zros uses for a RELIABLE profile. A context manager: undeclares and
    closes on the way out, whatever happened."""

    def __init__(self) -> None:
        import zenoh
        from zros.config import open_session, settings_from_env
        self._zenoh = zenoh
        self._settings = settings_from_env()
        self.session, self.is_hub = open_session(self._settings)
        self._handles: list[Any] = []

    def _key(self, topic: str) -> str:
        from zros.keys import topic_key
        return topic_key(self._settings.domain_id, topic)

    def publisher(self, topic: str) -> Any:
        zenoh = self._zenoh
        pub = self.session.declare_publisher(self._key(topic), congestion_control=zenoh.CongestionControl.BLOCK,
                                             reliability=zenoh.Reliability.RELIABLE)
        self._handles.append(pub)
        return pub

    def subscriber(self, topic: str, callback: Callable[[Any], None]) -> Any:
        sub = self.session.declare_subscriber(self._key(topic), callback)
        self._handles.append(sub)
        return sub

    def __enter__(self) -> 'RawSide':
        return self

    def __exit__(self, *exc: object) -> None:
        for handle in reversed(self._handles):
            try:
                handle.undeclare()
            except Exception:  # noqa: BLE001 - closing anyway
                pass
        self.session.close()


class ZrosSide:
    """zros.init, one node and a SingleThreadedExecutor; a context manager that shuts all of
    it down on the way out, whatever happened."""

    def __init__(self, name: str) -> None:
        import zros
        from zros.executors import SingleThreadedExecutor
        from zros.node import Node
        self._zros = zros
        self.context = zros.init(args=['pubsub_bench'])
        self.is_hub = self.context.is_hub
        self.node = Node(name)
        self.executor = SingleThreadedExecutor()
        self.executor.add_node(self.node)

    def __enter__(self) -> 'ZrosSide':
        return self

    def __exit__(self, *exc: object) -> None:
        try:
            self.executor.shutdown()
            self.node.destroy_node()
        finally:
            self._zros.shutdown()


def percentile(sorted_values: list[int], q: float) -> float:
    """Nearest-rank percentile of an ascending list."""
    index = min(len(sorted_values), max(1, math.ceil(q / 100 * len(sorted_values)))) - 1
    return sorted_values[index]


# -- latency ----------------------------------------------------------------------------
class PingChain:
    """The pinging side's bookkeeping, shared by both libraries.

    The first pong (answering one of the seq-0 kick-off pings, sent until the peer is there)
    starts the chain; each pong with the expected sequence number records a round trip and
    sends the next ping straight from the receiving callback, so only the transport and the
    library under test sit between two pings. Stray pongs are ignored.
    """

    def __init__(self, warmup: int, count: int, send: Callable[[int], None]) -> None:
        self.warmup, self.count, self.send = warmup, count, send
        self.expected = 0
        self.sent_ns = 0
        self.rtts: list[int] = []
        self.done = threading.Event()

    def on_pong(self, seq: int, now_ns: int) -> None:
        if seq != self.expected:
            return
        if seq > self.warmup:
            self.rtts.append(now_ns - self.sent_ns)
        if seq >= self.warmup + self.count:
            self.done.set()
            return
        self.expected = seq + 1
        self.sent_ns = time.perf_counter_ns()
        self.send(self.expected)


def ping_raw(side: RawSide, case: str, args: argparse.Namespace) -> dict:
    import msgpack
    wire = raw_wire(case)
    pub = side.publisher(PING_TOPIC)

    def send(seq: int) -> None:
        raw_set_seq(case, wire, seq)
        pub.put(msgpack.packb(wire))

    chain = PingChain(args.warmup, args.count, send)

    def on_pong(sample: Any) -> None:
        data = msgpack.unpackb(sample.payload.to_bytes())
        chain.on_pong(raw_get_seq(case, data), time.perf_counter_ns())

    side.subscriber(PONG_TOPIC, on_pong)
    emit('ready', is_hub=side.is_hub)
    kick = raw_wire(case)  # a copy of its own: the chain may start on the Zenoh thread meanwhile
    raw_set_seq(case, kick, 0)
    kick_payload = msgpack.packb(kick)
    deadline = time.monotonic() + args.timeout
    while chain.expected == 0 and time.monotonic() < deadline:
        pub.put(kick_payload)
        time.sleep(0.05)
    chain.done.wait(max(0.0, deadline - time.monotonic()))
    return {'rtts_ns': chain.rtts, 'complete': chain.done.is_set()}


def ping_zros(side: ZrosSide, case: str, args: argparse.Namespace) -> dict:
    from zros.task import Future
    msg, msg_type = zros_msg(case), zros_type(case)
    pub = side.node.create_publisher(msg_type, PING_TOPIC, 10)
    finished = Future()

    def send(seq: int) -> None:
        zros_set_seq(case, msg, seq)
        pub.publish(msg)

    chain = PingChain(args.warmup, args.count, send)

    def on_pong(reply: Any) -> None:
        chain.on_pong(zros_get_seq(case, reply), time.perf_counter_ns())
        if chain.done.is_set():
            finished.set_result(True)

    side.node.create_subscription(msg_type, PONG_TOPIC, on_pong, 10)
    emit('ready', is_hub=side.is_hub)
    deadline = time.monotonic() + args.timeout
    while chain.expected == 0 and time.monotonic() < deadline:
        send(0)
        side.executor.spin_once(timeout_sec=0.05)
    side.executor.spin_until_future_complete(finished, timeout_sec=max(0.0, deadline - time.monotonic()))
    return {'rtts_ns': chain.rtts, 'complete': chain.done.is_set()}


def echo_raw(side: RawSide, case: str, args: argparse.Namespace, stop: threading.Event) -> None:
    import msgpack
    pub = side.publisher(PONG_TOPIC)

    def on_ping(sample: Any) -> None:
        pub.put(msgpack.packb(msgpack.unpackb(sample.payload.to_bytes())))

    side.subscriber(PING_TOPIC, on_ping)
    emit('ready', is_hub=side.is_hub)
    stop.wait()


def echo_zros(side: ZrosSide, case: str, args: argparse.Namespace, stop: threading.Event) -> None:
    msg_type = zros_type(case)
    pub = side.node.create_publisher(msg_type, PONG_TOPIC, 10)
    side.node.create_subscription(msg_type, PING_TOPIC, pub.publish, 10)
    emit('ready', is_hub=side.is_hub)
    threading.Thread(target=lambda: (stop.wait(), side.executor.shutdown()), daemon=True).start()
    side.executor.spin()


# -- throughput --------------------------------------------------------------------------
_SEQ = struct.Struct('<Q')


class Counter:
    """What the counting side has seen: written by the receiving thread, read by the window
    thread (plain ints: reading one while it changes is safe under the GIL)."""

    def __init__(self) -> None:
        self.received = 0
        self.lost = 0
        self.last_seq = 0
        self.first = threading.Event()


def measure_window(counter: Counter, args: argparse.Namespace, payload_bytes: int,
                   extra: Callable[[], dict[str, int]] = dict) -> dict:
    """Wait for the first message, let the flow settle, then count over the window."""
    if not counter.first.wait(args.timeout):
        return {'error': 'no message arrived'}
    time.sleep(args.warmup_s)
    n0, x0, t0 = counter.received, extra(), time.perf_counter()
    time.sleep(args.window)
    n1, x1, t1 = counter.received, extra(), time.perf_counter()
    return {'received': n1 - n0, 'seconds': t1 - t0, 'payload_bytes': payload_bytes,
            **{k: x1[k] - x0[k] for k in x1}}


def count_raw(side: RawSide, case: str, args: argparse.Namespace) -> dict:
    import msgpack
    counter = Counter()

    def on_sample(sample: Any) -> None:
        msgpack.unpackb(sample.payload.to_bytes())
        seq = _SEQ.unpack(sample.attachment.to_bytes())[0]
        last = counter.last_seq
        if last and seq > last + 1:
            counter.lost += seq - last - 1
        counter.last_seq = seq
        counter.received += 1
        if not counter.first.is_set():
            counter.first.set()

    side.subscriber(FLOOD_TOPIC, on_sample)
    emit('ready', is_hub=side.is_hub)
    return measure_window(counter, args, len(msgpack.packb(raw_wire(case))),
                          lambda: {'lost': counter.lost, 'dropped': 0})


def count_zros(side: ZrosSide, case: str, args: argparse.Namespace) -> dict:
    from zros.executors import ExternalShutdownException
    from zros.message import serialize
    counter = Counter()

    def on_msg(msg: Any) -> None:
        counter.received += 1
        if not counter.first.is_set():
            counter.first.set()

    qos: Any = 10
    if args.worker[1].endswith('-keepall'):
        from zros.qos import HistoryPolicy, QoSProfile
        qos = QoSProfile(history=HistoryPolicy.KEEP_ALL)
    sub = side.node.create_subscription(zros_type(case), FLOOD_TOPIC, on_msg, qos)
    emit('ready', is_hub=side.is_hub)
    result: dict = {}

    def window() -> None:  # beside the spinning main thread
        try:
            result.update(measure_window(counter, args, len(serialize(zros_msg(case))),
                                         lambda: {'lost': sub.lost, 'dropped': sub.dropped}))
        finally:
            side.executor.shutdown()

    thread = threading.Thread(target=window, name='bench-window')
    thread.start()
    try:
        side.executor.spin()
    except ExternalShutdownException:
        pass
    thread.join()
    return result


def flood_raw(side: RawSide, case: str, args: argparse.Namespace, stop: threading.Event) -> None:
    import msgpack
    pub = side.publisher(FLOOD_TOPIC)
    wire = raw_wire(case)
    emit('ready', is_hub=side.is_hub)
    pack, put, seq_pack, stopped = msgpack.packb, pub.put, _SEQ.pack, stop.is_set
    seq = 0
    while not stopped():
        seq += 1
        put(pack(wire), attachment=seq_pack(seq))


def flood_zros(side: ZrosSide, case: str, args: argparse.Namespace, stop: threading.Event) -> None:
    pub = side.node.create_publisher(zros_type(case), FLOOD_TOPIC, 10)
    msg = zros_msg(case)
    emit('ready', is_hub=side.is_hub)
    publish, stopped = pub.publish, stop.is_set
    while not stopped():
        publish(msg)


# -- the user's path: Node subclasses spun as the ROS 2 tutorials spin them ----------------------
BUSY_TOPIC = '/zros_bench/busy'
#: The neighbour of `latency:busy`: its callback takes this long, and it gets this many messages a second.
BUSY_CALLBACK_S, BUSY_RATE_HZ = 0.05, 15.0


class NodeSide:
    """What a user's program has: `zros.init()`, its Node subclasses, `zros.spin(node)` (the
    global SingleThreadedExecutor) on the main thread or on a thread of its own; a context
    manager that shuts zros down on the way out."""

    def __init__(self) -> None:
        import zros
        self._zros = zros
        self.context = zros.init(args=['pubsub_bench'])
        self.is_hub = self.context.is_hub

    def spin_in_thread(self, node: Any, executor: Any = None) -> threading.Thread:
        """`threading.Thread(target=rclpy.spin, args=(node,))`, as a user's script starts it."""
        from zros.executors import ExternalShutdownException

        def spin() -> None:
            try:
                self._zros.spin(node, executor)
            except ExternalShutdownException:
                pass
        thread = threading.Thread(target=spin, daemon=True, name=f'spin-{node.get_name()}')
        thread.start()
        return thread

    def __enter__(self) -> 'NodeSide':
        return self

    def __exit__(self, *exc: object) -> None:
        self._zros.try_shutdown()   # (the echoing side's stop already shut it down)


def node_qos(args: argparse.Namespace) -> Any:
    """Depth 10, or KEEP_ALL for the `node-keepall` column."""
    if not args.worker[1].endswith('-keepall'):
        return 10
    from zros.qos import HistoryPolicy, QoSProfile
    return QoSProfile(history=HistoryPolicy.KEEP_ALL)


def ping_node(side: NodeSide, case: str, args: argparse.Namespace) -> dict:
    from zros.executors import SingleThreadedExecutor
    from zros.node import Node
    size = message_case(case)
    msg_type = zros_type(size)

    class Pinger(Node):
        def __init__(self) -> None:
            super().__init__('pinger')
            self.msg = zros_msg(size)
            self.pub = self.create_publisher(msg_type, PING_TOPIC, 10)
            self.chain = PingChain(args.warmup, args.count, self.send)
            self.create_subscription(msg_type, PONG_TOPIC, self.on_pong, 10)

        def send(self, seq: int) -> None:
            zros_set_seq(size, self.msg, seq)
            self.pub.publish(self.msg)

        def on_pong(self, msg: Any) -> None:
            self.chain.on_pong(zros_get_seq(size, msg), time.perf_counter_ns())

    class Busy(Node):
        """The slow neighbour of `latency:busy`: a KEEP_ALL subscription whose callback takes
        BUSY_CALLBACK_S, on an executor of its own (as a user keeps a slow callback apart)."""

        def __init__(self) -> None:
            from zros.qos import HistoryPolicy, QoSProfile
            super().__init__('busy')
            self.received = 0
            self.sub = self.create_subscription(msg_type, BUSY_TOPIC, self.on_msg,
                                                QoSProfile(history=HistoryPolicy.KEEP_ALL))

        def on_msg(self, msg: Any) -> None:
            self.received += 1
            time.sleep(BUSY_CALLBACK_S)

    node = Pinger()
    busy = Busy() if case == 'busy' else None
    if busy is not None:
        side.spin_in_thread(busy, SingleThreadedExecutor())
    side.spin_in_thread(node)
    emit('ready', is_hub=side.is_hub)
    chain, deadline = node.chain, time.monotonic() + args.timeout
    kick = zros_msg(size)   # a message of its own: the chain may start on the spinning thread meanwhile
    zros_set_seq(size, kick, 0)
    while chain.expected == 0 and time.monotonic() < deadline:
        node.pub.publish(kick)
        time.sleep(0.05)
    chain.done.wait(max(0.0, deadline - time.monotonic()))
    extra = {} if busy is None else {'busy_received': busy.received, 'busy_lost': busy.sub.lost,
                                     'busy_dropped': busy.sub.dropped}
    return {'rtts_ns': chain.rtts, 'complete': chain.done.is_set(), **extra}


def echo_node(side: NodeSide, case: str, args: argparse.Namespace, stop: threading.Event) -> None:
    from zros.executors import ExternalShutdownException
    from zros.node import Node
    msg_type = zros_type(message_case(case))

    class Echo(Node):
        def __init__(self) -> None:
            super().__init__('echo')
            self.pub = self.create_publisher(msg_type, PONG_TOPIC, 10)
            self.create_subscription(msg_type, PING_TOPIC, self.on_ping, 10)

        def on_ping(self, msg: Any) -> None:
            self.pub.publish(msg)

    node = Echo()
    if case == 'busy':
        threading.Thread(target=feed_busy, args=(node, stop), daemon=True, name='bench-busy').start()
    emit('ready', is_hub=side.is_hub)
    threading.Thread(target=lambda: (stop.wait(), side._zros.shutdown()), daemon=True).start()
    try:
        side._zros.spin(node)   # on the main thread, as a tutorial's main() does
    except ExternalShutdownException:
        pass


def feed_busy(node: Any, stop: threading.Event) -> None:
    """Publish to the pinging side's slow neighbour at BUSY_RATE_HZ until the run ends."""
    pub = node.create_publisher(zros_type('twist'), BUSY_TOPIC, 10)
    msg = zros_msg('twist')
    while not stop.wait(1 / BUSY_RATE_HZ):
        pub.publish(msg)


def count_node(side: NodeSide, case: str, args: argparse.Namespace) -> dict:
    from zros.message import serialize
    from zros.node import Node
    counter = Counter()

    class Listener(Node):
        def __init__(self) -> None:
            super().__init__('listener')
            self.sub = self.create_subscription(zros_type(case), FLOOD_TOPIC, self.on_msg, node_qos(args))

        def on_msg(self, msg: Any) -> None:
            counter.received += 1
            if not counter.first.is_set():
                counter.first.set()

    node = Listener()
    side.spin_in_thread(node)
    emit('ready', is_hub=side.is_hub)
    return measure_window(counter, args, len(serialize(zros_msg(case))),
                          lambda: {'lost': node.sub.lost, 'dropped': node.sub.dropped})


def flood_node(side: NodeSide, case: str, args: argparse.Namespace, stop: threading.Event) -> None:
    from zros.node import Node
    node = Node('talker')
    pub = node.create_publisher(zros_type(case), FLOOD_TOPIC, 10)
    msg = zros_msg(case)
    emit('ready', is_hub=side.is_hub)
    while not stop.is_set():
        pub.publish(msg)


class DdsSide:
    """A cyclonedds participant in the run's domain (loopback unicast, see worker_env), with the
    benchmark's Twist as an IDL struct; reliable, keep-last 10 readers and writers."""

    is_hub = True  # no hub in DDS: the orchestrator's hub check does not apply

    def __init__(self) -> None:
        from cyclonedds.core import Policy, Qos
        from cyclonedds.domain import DomainParticipant
        from cyclonedds.idl import IdlStruct

        def struct(name: str, fields: dict[str, type]) -> type:
            # Real type objects in __annotations__: this module's annotations are strings
            # (`from __future__ import annotations`), which cyclonedds cannot resolve.
            body = lambda ns: ns.update({'__annotations__': fields})  # noqa: E731
            return dataclass(types.new_class(name, (IdlStruct,), {'typename': f'geometry_msgs::msg::dds_::{name}_'},
                                             body))
        self.Vector3 = struct('Vector3', {'x': float, 'y': float, 'z': float})
        self.Twist = struct('Twist', {'linear': self.Vector3, 'angular': self.Vector3})
        self.participant = DomainParticipant(int(os.environ['ZROS_DOMAIN_ID']))
        self.qos = Qos(Policy.Reliability.Reliable(max_blocking_time=1_000_000_000), Policy.History.KeepLast(10))
        self._topics: dict[str, Any] = {}

    def _topic(self, name: str) -> Any:
        from cyclonedds.topic import Topic
        if name not in self._topics:
            self._topics[name] = Topic(self.participant, 'rt' + name, self.Twist)
        return self._topics[name]

    def message(self, seq: int) -> Any:
        return self.Twist(linear=self.Vector3(float(seq), 0.5, 0.0), angular=self.Vector3(0.0, 0.0, 0.25))

    def writer(self, name: str) -> Any:
        from cyclonedds.pub import DataWriter
        return DataWriter(self.participant, self._topic(name), self.qos)

    def reader(self, name: str, callback: Callable[[Any], None]) -> Any:
        from cyclonedds.core import Listener
        from cyclonedds.sub import DataReader

        def on_data(reader: Any) -> None:
            if reader is None:  # cyclonedds calls it once more while the reader is deleted
                return
            for sample in reader.take(64):
                callback(sample)
        return DataReader(self.participant, self._topic(name), self.qos, listener=Listener(on_data_available=on_data))

    def __enter__(self) -> 'DdsSide':
        return self

    def __exit__(self, *exc: object) -> None:
        self._topics.clear()


def ping_dds(side: DdsSide, case: str, args: argparse.Namespace) -> dict:
    writer = side.writer(PING_TOPIC)
    chain = PingChain(args.warmup, args.count, lambda seq: writer.write(side.message(seq)))
    reader = side.reader(PONG_TOPIC, lambda sample: chain.on_pong(int(sample.linear.x), time.perf_counter_ns()))
    emit('ready', is_hub=True)
    deadline = time.monotonic() + args.timeout
    while chain.expected == 0 and time.monotonic() < deadline:
        writer.write(side.message(0))
        time.sleep(0.05)
    chain.done.wait(max(0.0, deadline - time.monotonic()))
    del reader
    return {'rtts_ns': chain.rtts, 'complete': chain.done.is_set()}


def echo_dds(side: DdsSide, case: str, args: argparse.Namespace, stop: threading.Event) -> None:
    writer = side.writer(PONG_TOPIC)
    reader = side.reader(PING_TOPIC, writer.write)
    emit('ready', is_hub=True)
    stop.wait()
    del reader


def count_dds(side: DdsSide, case: str, args: argparse.Namespace) -> dict:
    counter = Counter()

    def on_sample(sample: Any) -> None:
        seq = int(sample.linear.x)
        last = counter.last_seq
        if last and seq > last + 1:
            counter.lost += seq - last - 1
        counter.last_seq = seq
        counter.received += 1
        if not counter.first.is_set():
            counter.first.set()
    reader = side.reader(FLOOD_TOPIC, on_sample)
    emit('ready', is_hub=True)
    result = measure_window(counter, args, 48, lambda: {'lost': counter.lost, 'dropped': 0})
    del reader
    return result


def flood_dds(side: DdsSide, case: str, args: argparse.Namespace, stop: threading.Event) -> None:
    writer = side.writer(FLOOD_TOPIC)
    emit('ready', is_hub=True)
    seq, write, message, stopped = 0, writer.write, side.message, stop.is_set
    while not stopped():
        seq += 1
        write(message(seq))


#: role -> (measuring?, {impl: function}). Measuring roles return a result and are the hub;
#: peers run until their stdin closes.
ROLES = {
    'ping': (True, {'raw': ping_raw, 'zros': ping_zros, 'node': ping_node, 'dds': ping_dds}),
    'echo': (False, {'raw': echo_raw, 'zros': echo_zros, 'node': echo_node, 'dds': echo_dds}),
    'count': (True, {'raw': count_raw, 'zros': count_zros, 'node': count_node, 'dds': count_dds}),
    'flood': (False, {'raw': flood_raw, 'zros': flood_zros, 'node': flood_node, 'dds': flood_dds}),
}
SIDES = {'raw': RawSide, 'dds': DdsSide, 'node': NodeSide}


def dds_available() -> bool:
    try:
        import cyclonedds.domain  # noqa: F401
    except ImportError:
        return False
    return True


def run_worker(args: argparse.Namespace) -> None:
    start_watchdog()
    stop = watch_stdin()
    role, impl, case = args.worker
    measuring, functions = ROLES[role]
    kind = impl.split('-')[0]  # zros-keepall is zros with another QoS
    with (SIDES[kind]() if kind in SIDES else ZrosSide(f'bench_{role}')) as side:
        fn = functions[kind]
        if measuring:
            emit('result', **fn(side, case, args))
            stop.wait()  # keep the session (the hub) up until the peer has gone
        else:
            fn(side, case, args, stop)


# ================================================================================ orchestration
class BenchError(RuntimeError):
    pass


class Child:
    """A worker process; its stdout lines are read on a thread so every wait has a timeout."""

    def __init__(self, argv: list[str], env: dict[str, str], label: str) -> None:
        self.label = label
        self.proc = subprocess.Popen([sys.executable, os.path.abspath(__file__), *argv], env=env,
                                     stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)
        self.lines: queue.Queue = queue.Queue()
        threading.Thread(target=self._read, daemon=True).start()

    def _read(self) -> None:
        for line in self.proc.stdout:
            self.lines.put(line)
        self.lines.put(None)

    def expect(self, event: str, timeout: float) -> dict:
        deadline = time.monotonic() + timeout
        while True:
            try:
                line = self.lines.get(timeout=max(0.0, deadline - time.monotonic()))
            except queue.Empty:
                raise BenchError(f'{self.label}: no {event!r} within {timeout:.0f} s') from None
            if line is None:
                raise BenchError(f'{self.label}: exited (code {self.proc.wait()}) before {event!r}')
            try:
                message = json.loads(line)
            except ValueError:
                print(f'[{self.label}] {line.rstrip()}', file=sys.stderr)
                continue
            if message.get('event') == event:
                return message

    def stop(self, timeout: float = 10.0) -> None:
        """Close stdin (the worker cleans up and exits); kill it if it does not."""
        try:
            self.proc.stdin.close()
        except OSError:
            pass
        try:
            self.proc.wait(timeout)
        except subprocess.TimeoutExpired:
            self.kill()
            raise BenchError(f'{self.label}: did not exit within {timeout:.0f} s of stop; killed') from None

    def kill(self) -> None:
        if self.proc.poll() is None:
            self.proc.kill()
            self.proc.wait()


def pick_domain(after: int = DOMAIN_BASE - 1) -> int:
    """The first domain after `after` whose loopback hub port is free (every benchmark's)."""
    from zros.config import hub_port_free
    for domain in range(after + 1, 233):
        if hub_port_free(domain):
            return domain
    raise BenchError(f'no free hub port for domains {after + 1}-232')


#: cyclonedds on loopback only, without multicast (the machine's rule for benchmarks).
CYCLONEDDS_LOOPBACK = ('<CycloneDDS><Domain Id="any"><General><Interfaces><NetworkInterface address="127.0.0.1"/>'
                       '</Interfaces><AllowMulticast>false</AllowMulticast></General><Discovery>'
                       '<ParticipantIndex>auto</ParticipantIndex><MaxAutoParticipantIndex>40</MaxAutoParticipantIndex>'
                       '<Peers><Peer Address="127.0.0.1"/></Peers></Discovery></Domain></CycloneDDS>')


def worker_env(domain: int, case: str = '') -> dict[str, str]:
    """Loopback-only zros defaults for `domain`, whatever the caller's environment says; a
    ':noshm' case turns shared memory off."""
    env = {k: v for k, v in os.environ.items()
           if k not in ('ZROS_CONNECT', 'ZROS_LISTEN', 'ZROS_DISCOVERY', 'ZROS_CONFIG', 'ROS_DOMAIN_ID')}
    env['ZROS_DOMAIN_ID'] = str(domain)
    env['ZROS_SHM_POOL_SIZE'] = '0' if case.endswith(':noshm') else SHM_POOL
    env['CYCLONEDDS_URI'] = CYCLONEDDS_LOOPBACK
    env['PYTHONPATH'] = os.pathsep.join(p for p in (str(REPO), env.get('PYTHONPATH')) if p)
    return env


def run_pair(measurer_argv: list[str], peer_argv: list[str], label: str, timeout: float) -> dict:
    """Start the measuring worker (the hub), then its peer; return the measurer's result.

    If something else takes the domain's hub port between our check and the worker's bind,
    the run moves to the next free domain (up to three tries)."""
    domain = DOMAIN_BASE - 1
    for _ in range(3):
        domain = pick_domain(domain)
        result = _run_pair_in(domain, measurer_argv, peer_argv, label, timeout)
        if result is not None:
            return result
    raise BenchError(f'{label}: the measuring worker never became the hub of its domain')


def _run_pair_in(domain: int, measurer_argv: list[str], peer_argv: list[str], label: str,
                 timeout: float) -> dict | None:
    env = worker_env(domain, measurer_argv[3])
    children: list[Child] = []
    try:
        measurer = Child(measurer_argv, env, f'{label} measurer')
        children.append(measurer)
        if not measurer.expect('ready', READY_S)['is_hub']:
            return None
        peer = Child(peer_argv, env, f'{label} peer')
        children.append(peer)
        peer.expect('ready', READY_S)
        result = measurer.expect('result', timeout)
        if result.get('error'):
            raise BenchError(f"{label}: {result['error']}")
        peer.stop()         # the peer first, so the hub's port is not left in TIME_WAIT
        measurer.stop()
        return result
    finally:
        for child in reversed(children):
            child.kill()


@dataclass
class Plan:
    lat_small: int
    lat_large: int
    warmup_small: int
    warmup_large: int
    window_s: float
    warmup_s: float
    throughput_cases: tuple[str, ...]
    lat_rounds: int
    tput_rounds: int


def latency_round(impl: str, case: str, count: int, warmup: int) -> 'Rtts':
    """One ping-pong run in fresh processes; the round-trip times in ns."""
    timeout = 20 + count * (0.02 if message_case(case) == 'twist' else 0.2)
    result = run_pair(['--worker', 'ping', impl, case, '--count', str(count), '--warmup', str(warmup),
                       '--timeout', str(timeout)],
                      ['--worker', 'echo', impl, case], f'latency {case} {impl}', timeout + 5)
    rtts = Rtts(result['rtts_ns'])
    rtts.busy = {k: v for k, v in result.items() if k.startswith('busy_')}
    if not result['complete'] or len(rtts) < count:
        raise BenchError(f'latency {case} {impl}: only {len(rtts)} of {count} round trips in {timeout:.0f} s')
    return rtts


class Rtts(list):
    """Round-trip times in ns, with what the slow neighbour of `latency:busy` counted."""

    busy: dict[str, int]


def latency_stats(rtts: list[int]) -> dict:
    rtts = sorted(rtts)
    return {'median': percentile(rtts, 50) / 1e3, 'p90': percentile(rtts, 90) / 1e3,
            'p99': percentile(rtts, 99) / 1e3, 'n': len(rtts)}


def throughput_round(impl: str, case: str, plan: 'Plan') -> dict:
    """One flood run in fresh processes: what the counting side saw in its window."""
    timeout = 15.0
    result = run_pair(['--worker', 'count', impl, case, '--window', str(plan.window_s),
                       '--warmup-s', str(plan.warmup_s), '--timeout', str(timeout)],
                      ['--worker', 'flood', impl, case], f'throughput {case} {impl}',
                      timeout + plan.warmup_s + plan.window_s + 5)
    return result


def throughput_stats(rounds: list[dict]) -> dict:
    received = sum(r['received'] for r in rounds)
    seconds = sum(r['seconds'] for r in rounds)
    rate = received / seconds
    return {'msgs': rate, 'mbps': rate * rounds[0]['payload_bytes'] / 1e6,
            'lost': sum(r['lost'] for r in rounds), 'dropped': sum(r['dropped'] for r in rounds),
            'arrived_msgs': sum(r['received'] + r['dropped'] for r in rounds) / seconds,
            'per_round_msgs': [r['received'] / r['seconds'] for r in rounds],
            'payload_bytes': rounds[0]['payload_bytes'], 'seconds': seconds}


def round_orders(rounds: int, impls: tuple[str, ...] = ('raw', 'zros')) -> list[tuple[str, ...]]:
    """raw, zros / zros, raw / ...: alternating, so drift in machine load hits all alike."""
    return [impls if i % 2 == 0 else impls[::-1] for i in range(rounds)]


def verdict(target: tuple[str, float], ratio: float) -> str:
    kind, bound = target
    ok = ratio <= bound if kind == 'max' else ratio >= bound
    return 'PASS' if ok else 'MISS'


def target_text(target: tuple[str, float]) -> str:
    kind, bound = target
    return f'<= {bound:.2f}x' if kind == 'max' else f'>= {bound:.2f}x'


def table(headers: list[str], rows: list[list[str]]) -> str:
    widths = [max(len(h), *(len(r[i]) for r in rows)) for i, h in enumerate(headers)]
    def line(cells: list[str]) -> str:
        return '  '.join(c.ljust(w) if i == 0 else c.rjust(w) for i, (c, w) in enumerate(zip(cells, widths)))
    return '\n'.join([line(headers), line(['-' * w for w in widths]), *(line(r) for r in rows)])


def machine_facts() -> dict:
    import msgpack
    from importlib.metadata import version
    cpu = platform.processor() or ''
    try:
        with open('/proc/cpuinfo') as f:
            cpu = next((line.split(':', 1)[1].strip() for line in f if line.startswith('model name')), cpu)
    except OSError:
        pass
    return {'nproc': os.cpu_count(), 'cpu': cpu, 'python': platform.python_version(),
            'eclipse-zenoh': version('eclipse-zenoh'), 'msgpack': '.'.join(map(str, msgpack.version)),
            'cyclonedds': version('cyclonedds') if dds_available() else 'not installed',
            'platform': platform.platform()}


def run_orchestrator(args: argparse.Namespace) -> int:
    plan = (Plan(lat_small=500, lat_large=50, warmup_small=100, warmup_large=10, window_s=1.0, warmup_s=0.3,
                 throughput_cases=('twist', '1MB', '8MB'), lat_rounds=1, tput_rounds=1)
            if args.quick else
            Plan(lat_small=2000, lat_large=200, warmup_small=200, warmup_large=20, window_s=2.0, warmup_s=0.5,
                 throughput_cases=('twist', '64KB', '1MB', '1MB:noshm', '8MB', '8MB:noshm', '32MB', '32MB:noshm'),
                 lat_rounds=6, tput_rounds=3))
    if args.rounds:
        plan.lat_rounds = plan.tput_rounds = args.rounds
    wanted = set(args.only.split(',')) if args.only else None
    dds = ('dds',) if dds_available() else ()
    facts = machine_facts()
    print(f"zros pub/sub benchmark{' (quick)' if args.quick else ''}: nproc={facts['nproc']} "
          f"python={facts['python']} eclipse-zenoh={facts['eclipse-zenoh']} msgpack={facts['msgpack']} "
          f"cyclonedds={facts['cyclonedds']}")
    print(f"cpu: {facts['cpu']}")
    started = time.monotonic()

    latency: dict[str, dict[str, dict]] = {}
    busy_counts: dict[str, dict[str, int]] = {}
    node = ('node',) if args.node else ()
    busy = (('busy', plan.lat_small, plan.warmup_small),) if args.node else ()
    for case, count, warmup in (('twist', plan.lat_small, plan.warmup_small),
                                ('1MB', plan.lat_large, plan.warmup_large), *busy):
        if wanted is not None and f'latency:{case}' not in wanted:
            continue
        impls = {'twist': ('raw', 'zros', *node, *dds), 'busy': node}.get(case, ('raw', 'zros', *node))
        samples: dict[str, list[int]] = {impl: [] for impl in impls}
        for i, order in enumerate(round_orders(plan.lat_rounds, impls)):
            for impl in order:
                print(f'  latency    {case:10} {impl:12} round {i + 1}/{plan.lat_rounds} ...', end=' ', flush=True)
                rtts = latency_round(impl, case, count // plan.lat_rounds, warmup)
                samples[impl] += rtts
                res = latency_stats(rtts)
                print(f"median {res['median']:.0f} us, p99 {res['p99']:.0f} us ({res['n']} round trips)"
                      + (f", busy neighbour got {rtts.busy['busy_received']}, lost {rtts.busy['busy_lost']}"
                         if rtts.busy else ''))
                busy_counts[impl] = {k: busy_counts.get(impl, {}).get(k, 0) + v for k, v in rtts.busy.items()}
        latency[case] = {impl: {**latency_stats(rtts), **busy_counts.get(impl, {})} for impl, rtts in samples.items()}

    throughput: dict[str, dict[str, dict]] = {}
    for case in plan.throughput_cases:
        if wanted is not None and f'throughput:{case}' not in wanted:
            continue
        # The small message also with a KEEP_ALL subscription: depth 10 should deliver as much.
        impls = (('raw', 'zros', 'zros-keepall', *node, *(f'{n}-keepall' for n in node), *dds) if case == 'twist'
                 else ('raw', 'zros', *node))
        rounds: dict[str, list[dict]] = {impl: [] for impl in impls}
        for i, order in enumerate(round_orders(plan.tput_rounds, impls)):
            for impl in order:
                print(f'  throughput {case:10} {impl:12} round {i + 1}/{plan.tput_rounds} ...', end=' ', flush=True)
                result = throughput_round(impl, case, plan)
                rounds[impl].append(result)
                rate = result['received'] / result['seconds']
                print(f"{rate:.0f} msg/s, {rate * result['payload_bytes'] / 1e6:.1f} MB/s, "
                      f"lost {result['lost']}, dropped {result['dropped']}")
        throughput[case] = {impl: throughput_stats(r) for impl, r in rounds.items()}

    stages = copy_stages('8MB') if wanted is None or 'copies' in wanted else None
    print()
    print(report(latency, throughput, plan, stages, bool(dds)))
    print(f'\ntotal wall time {time.monotonic() - started:.1f} s')
    if args.json:
        Path(args.json).write_text(json.dumps({'facts': facts, 'plan': plan.__dict__, 'latency': latency,
                                               'throughput': throughput, 'copies': stages}, indent=2))
    return 0


def case_name(case: str) -> str:
    size, _, variant = case.partition(':')
    name = 'Twist' if size == 'twist' else f'Image {size[:-2]} {size[-2:]}'
    return name + (', no SHM' if variant == 'noshm' else ', SHM' if size in ('8MB', '32MB') else '')


def copy_stages(case: str, repeat: int = 20) -> dict:
    """Time each copy of a large payload between publish() and the callback, in this process:
    zros's path (serialize, the copy into shared memory or into Zenoh's buffer, to_bytes on
    receive, decode into an array.array) against the protocol v1 path (a msgpack map with the
    pixels inline as bin: packb, the copy into Zenoh's buffer, to_bytes, unpackb)."""
    import msgpack
    import zenoh

    from zros.message import deserialize, serialize
    msg = zros_msg(case)
    v1 = {'header': {'stamp': {'sec': 0, 'nanosec': 0}, 'frame_id': 'camera'}, 'height': msg.height,
          'width': msg.width, 'encoding': 'rgb8', 'is_bigendian': 0, 'step': msg.step, 'data': pixels(case)}

    def ms(fn: Callable[[], Any]) -> float:
        fn()
        start = time.perf_counter()
        for _ in range(repeat):
            fn()
        return (time.perf_counter() - start) / repeat * 1e3

    os.environ.setdefault('ZROS_SHM_POOL_SIZE', SHM_POOL)
    payload = serialize(msg)
    v1_payload = msgpack.packb(v1)
    in_zenoh = zenoh.ZBytes(payload)
    return {
        'size': len(payload),
        'zros': [('serialize (header + one copy of the pixels)', ms(lambda: serialize(msg))),
                 ('into a Zenoh buffer (Zenoh then copies it into its shared-memory pool)', ms(lambda: zenoh.ZBytes(payload))),
                 ('to_bytes on receive', ms(in_zenoh.to_bytes)),
                 ('decode into array.array', ms(lambda: deserialize(payload, type(msg))))],
        'v1': [('msgpack.packb of the field map', ms(lambda: msgpack.packb(v1))),
               ('into a Zenoh buffer', ms(lambda: zenoh.ZBytes(v1_payload))),
               ('to_bytes on receive', ms(zenoh.ZBytes(v1_payload).to_bytes)),
               ('msgpack.unpackb (pixels as bytes)', ms(lambda: msgpack.unpackb(v1_payload)))],
    }


def report(latency: dict, throughput: dict, plan: Plan, stages: dict | None, dds: bool) -> str:
    """The comparison tables, each row judged against its target (docs/architecture.md §8, issue 21)."""
    out = []
    rows = []
    for case, res in latency.items():
        if 'raw' not in res:
            continue   # latency:busy has the node column only (user_path_rows)
        raw, zr, dd = res['raw'], res['zros'], res.get('dds')
        target = LATENCY_TARGET if case == 'twist' else LARGE_LATENCY_TARGET
        for stat in ('median', 'p90', 'p99'):
            ratio = zr[stat] / raw[stat]
            judged = stat == 'median'
            rows.append([f'{case_name(case)} RTT {stat}', f'{raw[stat]:.0f}', f'{zr[stat]:.0f}', f'{ratio:.2f}x',
                         target_text(target) if judged else '(info)', verdict(target, ratio) if judged else '',
                         f'{dd[stat]:.0f}' if dd else '-'])
    if rows:
        n = ', '.join(f"{case_name(c)} {r['raw']['n']}" for c, r in latency.items() if 'raw' in r)
        out += [f'Round-trip latency in us, ping-pong between two processes '
                f'({plan.lat_rounds} alternating runs each; round trips: {n})',
                table(['case', 'raw zenoh', 'zros', 'zros/raw', 'target', 'result', 'cyclonedds'], rows), '']
    rows, loss_rows = [], []
    for case, res in throughput.items():
        raw = res['raw']
        size = case.split(':')[0]
        for impl, label in (('zros', ', depth 10' if size == 'twist' else ''), ('zros-keepall', ', KEEP_ALL')):
            if impl not in res:
                continue
            zr = res[impl]
            ratio = zr['msgs'] / raw['msgs']
            if size == 'twist':
                target = SMALL_RATE_TARGET if impl == 'zros-keepall' else DEPTH10_TARGET
                if target is DEPTH10_TARGET and 'zros-keepall' not in res:
                    target = None
            else:
                target = RATE_TARGETS.get(size) if not case.endswith(':noshm') or size == '1MB' else None
            if target is not None and target[0] == 'abs':
                judged, shown = zr['msgs'], f'>= {target[1]:.0f} msg/s'
            elif target is DEPTH10_TARGET and 'zros-keepall' in res:
                judged = zr['msgs'] / res['zros-keepall']['msgs']
                shown = f'{target_text(target)} of KEEP_ALL'
            else:
                judged, shown = ratio, target_text(target) if target else '(info)'
            dd = res.get('dds') if impl == 'zros' else None
            rows.append([case_name(case) + label, f"{raw['msgs']:.0f}", f"{zr['msgs']:.0f}", f"{raw['mbps']:.1f}",
                         f"{zr['mbps']:.1f}", f'{ratio:.2f}x', shown, verdict(target, judged) if target else '',
                         f"{dd['msgs']:.0f}" if dd else '-'])
            loss_rows.append([case_name(case) + label, str(raw['lost']), str(zr['lost']), str(zr['dropped']),
                              f"{zr['arrived_msgs']:.0f}"])
    if rows:
        out += [f'Throughput: messages received per second, reliable, publisher as fast as it can '
                f'({plan.tput_rounds} alternating runs x {plan.window_s:g} s window each)',
                table(['case', 'raw msg/s', 'zros msg/s', 'raw MB/s', 'zros MB/s', 'zros/raw', 'target', 'result',
                       'cyclonedds msg/s'], rows), '',
                'Losses in the same windows',
                table(['case', 'raw lost', 'zros lost', 'zros dropped', 'zros arrived msg/s'], loss_rows),
                'lost: gaps in the publisher\'s sequence numbers seen by the subscriber, before any queue;',
                'dropped: samples the zros subscription queue (KEEP_LAST 10, or KEEP_ALL = 100000) discarded '
                'because the executor fell behind;',
                'arrived: what reached the zros subscription (received + dropped).']
        if not dds:
            out.append('cyclonedds: not installed here (pip install cyclonedds) - its columns are empty.')
    node_rows = user_path_rows(latency, throughput)
    if node_rows:
        out += ['', "The user's path (--node): Node subclasses, zros.spin(node) on a thread of their own or the "
                    'main thread; ratios to raw zenoh-python in the same run',
                table(['case', 'raw', 'zros (micro)', 'node', 'node/raw', 'target', 'result', 'cyclonedds'], node_rows)]
    if stages:
        out += ['', f"Copies of an {stages['size'] / 1e6:.1f} MB payload between publish() and the callback, "
                    f'ms each (one process)',
                table(['zros (protocol v2)', 'ms'], [[k, f'{v:.2f}'] for k, v in stages['zros']]),
                table(['protocol v1 (msgpack map)', 'ms'], [[k, f'{v:.2f}'] for k, v in stages['v1']])]
    return '\n'.join(out)


def user_path_rows(latency: dict, throughput: dict) -> list[list[str]]:
    """The `node` column against raw and the micro path, judged by the same targets; the busy
    row's p99 against the plain round trip's, with what the slow neighbour lost."""
    rows = []
    for case, res in latency.items():
        if 'node' not in res or 'raw' not in res:
            continue
        target = LATENCY_TARGET if case == 'twist' else LARGE_LATENCY_TARGET
        raw, zr, nd, dd = res['raw'], res['zros'], res['node'], res.get('dds')
        for stat in ('median', 'p99'):
            ratio = nd[stat] / raw[stat]
            judged = stat == 'median'
            rows.append([f'{case_name(case)} RTT {stat}, us', f'{raw[stat]:.0f}', f'{zr[stat]:.0f}', f'{nd[stat]:.0f}',
                         f'{ratio:.2f}x', target_text(target) if judged else '(info)',
                         verdict(target, ratio) if judged else '', f'{dd[stat]:.0f}' if dd else '-'])
        if dd and case == 'twist':
            rows.append(['Twist RTT median against cyclonedds', '', '', '', f"{nd['median'] / dd['median']:.2f}x",
                         '<= 1.00x', verdict(('max', 1.0), nd['median'] / dd['median']), ''])
    busy = latency.get('busy', {}).get('node')
    plain = latency.get('twist', {}).get('node')
    if busy:
        ratio = f"{busy['p99'] / plain['p99']:.2f}x of plain" if plain else ''
        rows.append(['Twist RTT p99 beside a 50 ms callback, us', '', '', f"{busy['p99']:.0f}", ratio, '(against main)',
                     f"lost {busy.get('busy_lost', 0)}, got {busy.get('busy_received', 0)}", ''])
    twist = throughput.get('twist', {})
    if 'node' in twist:
        raw, keepall = twist['raw'], twist.get('node-keepall')
        if keepall:
            ratio = keepall['msgs'] / raw['msgs']
            rows.append(['Twist msg/s, KEEP_ALL', f"{raw['msgs']:.0f}", f"{twist['zros-keepall']['msgs']:.0f}",
                         f"{keepall['msgs']:.0f}", f'{ratio:.2f}x', target_text(SMALL_RATE_TARGET),
                         verdict(SMALL_RATE_TARGET, ratio), '-'])
        nd, dd = twist['node'], twist.get('dds')
        share = nd['msgs'] / keepall['msgs'] if keepall else None
        rows.append(['Twist msg/s, depth 10', f"{raw['msgs']:.0f}", f"{twist['zros']['msgs']:.0f}", f"{nd['msgs']:.0f}",
                     f'{share:.2f}x of KEEP_ALL' if share else '', f'{target_text(DEPTH10_TARGET)} of KEEP_ALL',
                     verdict(DEPTH10_TARGET, share) if share else '', f"{dd['msgs']:.0f}" if dd else '-'])
    for case, res in throughput.items():
        size = case.split(':')[0]
        if size == 'twist' or 'node' not in res:
            continue
        target = RATE_TARGETS.get(size) if not case.endswith(':noshm') or size == '1MB' else None
        raw, zr, nd = res['raw'], res['zros'], res['node']
        ratio = nd['msgs'] / raw['msgs']
        judged = nd['msgs'] if target and target[0] == 'abs' else ratio
        shown = (f'>= {target[1]:.0f} msg/s' if target[0] == 'abs' else target_text(target)) if target else '(info)'
        rows.append([f'{case_name(case)} msg/s', f"{raw['msgs']:.0f}", f"{zr['msgs']:.0f}", f"{nd['msgs']:.0f}",
                     f'{ratio:.2f}x', shown, verdict(target, judged) if target else '', '-'])
    return rows


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--quick', action='store_true', help='smaller counts, 1 s windows, fewer cases')
    parser.add_argument('--json', metavar='PATH', help='also write the raw numbers as JSON')
    parser.add_argument('--node', action='store_true',
                        help="also the user's path: Node subclasses spun by zros.spin (column 'node'), and the "
                             'Twist round trip beside a node whose callback takes 50 ms (latency:busy)')
    parser.add_argument('--rounds', type=int, help='runs per case and library, alternating raw/zros '
                                                    '(default 2, 1 with --quick)')
    parser.add_argument('--only', metavar='CASES',
                        help='comma-separated subset: latency:twist, latency:1MB, throughput:twist, '
                             'throughput:64KB, throughput:1MB, throughput:8MB, throughput:8MB:noshm, ... , copies')
    # Worker mode (used by the orchestrator, not meant to be run by hand).
    parser.add_argument('--worker', nargs=3, metavar=('ROLE', 'IMPL', 'CASE'), help=argparse.SUPPRESS)
    parser.add_argument('--count', type=int, default=1000, help=argparse.SUPPRESS)
    parser.add_argument('--warmup', type=int, default=100, help=argparse.SUPPRESS)
    parser.add_argument('--window', type=float, default=3.0, help=argparse.SUPPRESS)
    parser.add_argument('--warmup-s', type=float, default=0.5, help=argparse.SUPPRESS)
    parser.add_argument('--timeout', type=float, default=30.0, help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.worker:
        run_worker(args)
        return 0
    # SIGTERM unwinds like Ctrl-C, so every `finally` kills the workers of the current run.
    signal.signal(signal.SIGTERM, lambda signum, frame: sys.exit(128 + signum))
    try:
        return run_orchestrator(args)
    except KeyboardInterrupt:
        print('\ninterrupted', file=sys.stderr)
        return 130
    except BenchError as exc:
        print(f'\nbenchmark failed: {exc}', file=sys.stderr)
        return 1


if __name__ == '__main__':
    sys.exit(main())
