"""TF speed: buffer lookups per second, and how long a transform takes to reach a listener.

    python benchmarks/tf.py            # about 20 s
    python benchmarks/tf.py --quick    # a few seconds

1. Lookups (one process, no transport): a five-frame chain map -> odom -> base_footprint ->
   base_link -> base_scan whose four links are all dynamic (50 Hz, 2 s of history), looked up
   with `Buffer.lookup_transform` at times between samples, so every link is interpolated
   (slerp), and at `Time()` (latest). Goal: >= 50,000 lookups/s for the interpolated chain.
2. Latency (two processes on loopback): a sender publishes, at 100 Hz and interleaved, the same
   one-transform TFMessage (stamped with the wall clock at send time) three ways: its zros
   serialization on a raw zenoh-python key, on a plain zros topic, and through a
   TransformBroadcaster on /tf. This process receives: a raw Zenoh callback that decodes it, a
   zros subscription callback (run by the executor), and a TransformListener's buffer (time of
   the insert). One-way latency = receive - stamp,
   same machine clock. There is no set goal; the listener should be no slower than the topic.
"""
from __future__ import annotations

import argparse
import json
import math
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(REPO), str(Path(__file__).resolve().parent)]

from pubsub import machine_facts, pick_domain, table, worker_env  # noqa: E402

LOOKUP_GOAL = 50_000
RAW_KEY = 'zros_bench/tf_raw'
CHAIN = ('map', 'odom', 'base_footprint', 'base_link', 'base_scan')


def filled_buffer():
    """A Buffer with the five-frame chain, every link dynamic at 50 Hz for 2 s."""
    from zros.tf2_ros import Buffer
    buffer = Buffer()
    for k in range(100):
        stamp = 1_000_000_000 + k * 20_000_000
        for i, (parent, child) in enumerate(zip(CHAIN, CHAIN[1:])):
            yaw = 0.01 * k * (i + 1)
            buffer._insert(child, parent, stamp, (0.1 * k, 0.05 * i, 0.01, 0.0, 0.0, math.sin(yaw / 2),
                                                  math.cos(yaw / 2)), 'bench', False, 'bench')
    return buffer


def lookup_rate(times: list, rounds: int, count: int) -> tuple[float, float]:
    """Median (lookups per wall second, lookups per CPU second of this process) over `rounds`
    runs of `count` lookups cycling through `times`. The CPU-time rate is what one core gives
    when the machine is shared; on a quiet machine the two agree."""
    buffer = filled_buffer()
    wall, cpu = [], []
    for _ in range(rounds):
        started, started_cpu = time.perf_counter(), time.process_time()
        for i in range(count):
            buffer.lookup_transform('map', 'base_scan', times[i % len(times)])
        wall.append(count / (time.perf_counter() - started))
        cpu.append(count / (time.process_time() - started_cpu))
    return statistics.median(wall), statistics.median(cpu)


def bench_lookups(rounds: int, count: int) -> list[list[str]]:
    from zros.time import Time
    between = [Time(nanoseconds=1_000_000_000 + k * 20_000_000 + 7_000_000) for k in range(99)]
    interpolated = lookup_rate(between, rounds, count)
    latest = lookup_rate([Time()], rounds, count)
    verdict = 'met' if interpolated[1] >= LOOKUP_GOAL else 'MISSED'
    return [['5-frame chain, interpolated', f'{interpolated[0]:,.0f}', f'{interpolated[1]:,.0f}',
             f'>= {LOOKUP_GOAL:,}', verdict],
            ['5-frame chain, Time() latest', f'{latest[0]:,.0f}', f'{latest[1]:,.0f}', '-', '-']]


def run_sender(count: int) -> None:
    """The sender process: the same TFMessage three ways, interleaved, at 100 Hz."""
    import zros
    from zros.message import serialize
    from zros.node import Node
    from zros.tf2_ros import TransformBroadcaster
    from interfaces.geometry_msgs.msg import TransformStamped
    from interfaces.tf2_msgs.msg import TFMessage
    context = zros.init([])
    node = Node('tf_bench_sender')
    broadcaster = TransformBroadcaster(node)
    topic = node.create_publisher(TFMessage, '/tf_bench_topic', 100)
    raw = context.session.declare_publisher(RAW_KEY)
    time.sleep(1.0)  # let the receiver's subscriptions match
    t = TransformStamped()
    t.header.frame_id, t.child_frame_id = 'bench_parent', 'bench_child'
    t.transform.rotation.w = 1.0
    for _ in range(count):
        for send in ('raw', 'topic', 'tf'):
            now = time.time_ns()
            t.header.stamp.sec, t.header.stamp.nanosec = divmod(now, 1_000_000_000)
            message = TFMessage(transforms=[t])
            if send == 'raw':
                raw.put(serialize(message))
            elif send == 'topic':
                topic.publish(message)
            else:
                broadcaster.sendTransform(t)
            time.sleep(0.0033)
    time.sleep(0.5)
    zros.shutdown()


def bench_latency(count: int, domain: int) -> list[list[str]]:
    import zros
    from zros.executors import SingleThreadedExecutor
    from zros.message import deserialize
    from zros.node import Node
    from zros.tf2_ros import Buffer, TransformListener
    from interfaces.tf2_msgs.msg import TFMessage
    samples: dict[str, list[int]] = {'raw': [], 'topic': [], 'tf': []}

    def stamp_ns(stamp) -> int:
        return stamp.sec * 1_000_000_000 + stamp.nanosec

    class TimedBuffer(Buffer):
        def _on_new_data(self) -> None:
            now = time.time_ns()
            samples['tf'].append(now - self._caches['bench_child'].stamps[-1])

    os.environ.update(worker_env(domain))
    context = zros.init([])
    node = Node('tf_bench_receiver')
    TransformListener(TimedBuffer(), node)
    node.create_subscription(TFMessage, '/tf_bench_topic',
                             lambda m: samples['topic'].append(time.time_ns() - stamp_ns(m.transforms[0].header.stamp)),
                             100)

    def on_raw(sample) -> None:
        message = deserialize(sample.payload.to_bytes(), TFMessage)
        samples['raw'].append(time.time_ns() - stamp_ns(message.transforms[0].header.stamp))
    raw = context.session.declare_subscriber(RAW_KEY, on_raw)
    sender = subprocess.Popen([sys.executable, __file__, '--sender', str(count)], env=worker_env(domain))
    executor = SingleThreadedExecutor()
    executor.add_node(node)
    deadline = time.monotonic() + count * 0.012 + 20
    while sender.poll() is None and time.monotonic() < deadline:
        executor.spin_once(timeout_sec=0.05)
    sender.kill()
    raw.undeclare()
    zros.shutdown()
    rows = []
    for name, label in (('raw', 'raw zenoh-python callback'), ('topic', 'zros topic, subscription callback'),
                        ('tf', 'TransformListener -> Buffer insert')):
        values = sorted(samples[name])
        if not values:
            rows.append([label, '0', '-', '-', '-'])
            continue
        rows.append([label, str(len(values)), f'{values[len(values) // 2] / 1000:.0f}',
                     f'{values[int(len(values) * 0.9)] / 1000:.0f}', f'{values[int(len(values) * 0.99)] / 1000:.0f}'])
    return rows


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--quick', action='store_true', help='fewer rounds and samples')
    parser.add_argument('--json', help='also write the results to this file')
    parser.add_argument('--sender', type=int, help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.sender is not None:
        run_sender(args.sender)
        return 0
    rounds, count, messages = (3, 10_000, 200) if args.quick else (7, 30_000, 1000)
    facts = machine_facts()
    print(f"{facts['cpu']} ({facts['nproc']} cores), Python {facts['python']}, eclipse-zenoh {facts['eclipse-zenoh']}")
    lookups = bench_lookups(rounds, count)
    print('\nBuffer.lookup_transform (median of %d rounds of %d lookups)' % (rounds, count))
    print(f'load average at start: {os.getloadavg()[0]:.1f}')
    print(table(['case', 'lookups/wall s', 'lookups/CPU s', 'goal (CPU s)', 'verdict'], lookups))
    latency = bench_latency(messages, pick_domain())
    print('\nOne-way latency, sender process -> this process [us]')
    print(table(['path', 'samples', 'median', 'p90', 'p99'], latency))
    if args.json:
        Path(args.json).write_text(json.dumps({'machine': facts, 'lookups': lookups, 'latency': latency}, indent=2))
    return 0


if __name__ == '__main__':
    sys.exit(main())
