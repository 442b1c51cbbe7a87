"""rosbridge against a direct zros subscription: messages per second and latency, same run.

    python benchmarks/rosbridge.py            # about 40 s
    python benchmarks/rosbridge.py --quick    # about 15 s

A publisher process sends `sensor_msgs/Image` messages (a 1x1 image, the small case, and a
320x240 rgb8 one, 230 KB) with the send time (CLOCK_MONOTONIC, which every process on the machine
shares) in header.stamp and a sequence number in header.frame_id. This process receives each
message twice: through a zros subscription of its own (the direct path) and through
`rosbridge_server rosbridge_websocket` as a WebSocket client (JSON; CBOR too for the large
image). Latency is one way, publish to receipt, at 50 msg/s; throughput is what each path
delivers while the publisher sends as fast as it can. All traffic stays on loopback.
"""
from __future__ import annotations

import argparse
import json
import os
import re
import subprocess
import sys
import threading
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(REPO), str(Path(__file__).resolve().parent)]

from pubsub import machine_facts, percentile, pick_domain, table, worker_env  # noqa: E402

TOPIC = '/bench_images'
CASES = {'small': (1, 1), 'image': (320, 240)}    # width, height of an rgb8 image [px]
LATENCY_RATE = 50                                   # [msg/s]
WARM_UP = 1.0    # [s] of messages at LATENCY_RATE first, not counted: both paths' first-message costs


def publish(case: str, rate: float, seconds: float) -> None:
    """The publisher process: wait for both subscriptions, then send for `seconds` (rate 0: flat out)."""
    import zros
    from zros.node import Node

    from interfaces.sensor_msgs.msg import Image
    width, height = CASES[case]
    with zros.init([]):
        node = Node('bench_publisher')
        publisher = node.create_publisher(Image, TOPIC, 100)
        deadline = time.monotonic() + 30
        while node.count_subscribers(TOPIC) < 2 and time.monotonic() < deadline:
            time.sleep(0.05)
        msg = Image(width=width, height=height, encoding='rgb8', step=3 * width, data=bytes(3 * width * height))
        for warm_up, phase_rate, phase_seconds in ((True, LATENCY_RATE, WARM_UP), (False, rate, seconds)):
            end = time.monotonic() + phase_seconds
            seq = 0
            while time.monotonic() < end:
                now = time.monotonic_ns()
                msg.header.stamp.sec, msg.header.stamp.nanosec = divmod(now, 1_000_000_000)
                msg.header.frame_id = 'warm-up' if warm_up else str(seq)
                publisher.publish(msg)
                seq += 1
                if phase_rate:
                    time.sleep(max(0.0, 1.0 / phase_rate - (time.monotonic_ns() - now) / 1e9))
        print(f'sent {seq}', flush=True)


class Receipts:
    """One receiving path's record: receipt latencies [ns] and the count."""

    def __init__(self) -> None:
        self.latencies: list[int] = []
        self.first = self.last = 0

    def record(self, header: dict | object, received: int) -> None:
        frame_id, stamp = (header['frame_id'], header['stamp']) if isinstance(header, dict) else (header.frame_id,
                                                                                                   header.stamp)
        if frame_id == 'warm-up':
            return
        sec, nanosec = (stamp['sec'], stamp['nanosec']) if isinstance(stamp, dict) else (stamp.sec, stamp.nanosec)
        self.latencies.append(received - (sec * 1_000_000_000 + nanosec))
        self.first = self.first or received
        self.last = received


def bridge_client(url: str, compression: str, path: Receipts, stop: threading.Event) -> threading.Thread:
    """A WebSocket client subscribed to TOPIC through the bridge, recording into `path`."""
    from websockets.sync.client import connect
    ws = connect(url, max_size=None)
    ws.send(json.dumps({'op': 'subscribe', 'topic': TOPIC, 'type': 'sensor_msgs/msg/Image',
                        'compression': compression}))

    def read() -> None:
        import cbor2
        while not stop.is_set():
            try:
                frame = ws.recv(timeout=0.2)
            except TimeoutError:
                continue
            received = time.monotonic_ns()
            message = cbor2.loads(frame) if isinstance(frame, bytes) else json.loads(frame)
            if message.get('op') == 'publish':
                path.record(message['msg']['header'], received)
        ws.close()
    thread = threading.Thread(target=read, daemon=True)
    thread.start()
    return thread


def run_phase(env: dict, url: str, node, case: str, rate: float, seconds: float, compression: str) -> dict:
    """One publisher run, received directly and through the bridge."""
    from interfaces.sensor_msgs.msg import Image
    direct, bridged, stop = Receipts(), Receipts(), threading.Event()
    subscription = node.create_subscription(Image, TOPIC, lambda m: direct.record(m.header,
                                                                                  time.monotonic_ns()), 100)
    reader = bridge_client(url, compression, bridged, stop)
    publisher = subprocess.run([sys.executable, __file__, '--publish', case, str(rate), str(seconds)],
                               env=env, capture_output=True, text=True, timeout=seconds + WARM_UP + 60)
    sent = int(re.search(r'sent (\d+)', publisher.stdout).group(1))
    deadline = time.monotonic() + 10
    while (len(direct.latencies) < sent or len(bridged.latencies) < sent) and time.monotonic() < deadline:
        time.sleep(0.1)
    stop.set()
    reader.join(5)
    node.destroy_subscription(subscription)
    return {'sent': sent, 'direct': direct, 'bridge': bridged}


def spin_quietly(executor) -> None:
    """Spin until the context shuts down at the end of the run, which is not an error here."""
    from zros.executors import ExternalShutdownException
    try:
        executor.spin()
    except ExternalShutdownException:
        pass


def summary(label: str, path: Receipts, sent: int, seconds: float) -> list[str]:
    values = sorted(path.latencies)
    if not values:
        return [label, '0', '-', '-', '-', f'{sent}']
    span = max((path.last - path.first) / 1e9, 1e-9)
    return [label, f'{len(values) / max(span, seconds):.0f}', f'{percentile(values, 50) / 1e6:.2f}',
            f'{percentile(values, 90) / 1e6:.2f}', f'{percentile(values, 99) / 1e6:.2f}', f'{len(values)}/{sent}']


def main(args: argparse.Namespace) -> int:
    import zros
    from zros.executors import MultiThreadedExecutor
    from zros.node import Node
    seconds = 2.0 if args.quick else 5.0
    domain = pick_domain()
    env = worker_env(domain)
    os.environ.update(env)
    bridge = subprocess.Popen([sys.executable, '-m', 'zros', 'run', 'rosbridge_server', 'rosbridge_websocket',
                               '--ros-args', '-p', 'port:=0', '-p', 'address:=127.0.0.1'], env=env,
                              stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, start_new_session=True)
    try:
        port = None
        for line in bridge.stdout:
            found = re.search(r'started on port (\d+)', line)
            if found:
                port = int(found.group(1))
                break
        if port is None:
            print('the bridge did not start', file=sys.stderr)
            return 1
        threading.Thread(target=lambda: [None for _ in bridge.stdout], daemon=True).start()
        url = f'ws://127.0.0.1:{port}'
        rows = []
        with zros.init([]):
            node = Node('bench_receiver')
            executor = MultiThreadedExecutor(num_threads=2)
            executor.add_node(node)
            threading.Thread(target=spin_quietly, args=(executor,), daemon=True).start()
            for case, compression in (('small', 'none'), ('image', 'none'), ('image', 'cbor')):
                for mode, rate in (('latency', LATENCY_RATE), ('throughput', 0)):
                    result = run_phase(env, url, node, case, rate, seconds, compression)
                    name = f'{case} {mode}'
                    rows.append(summary(f'{name}: direct zros', result['direct'], result['sent'], seconds))
                    rows.append(summary(f'{name}: rosbridge {"CBOR" if compression == "cbor" else "JSON"}',
                                        result['bridge'], result['sent'], seconds))
                    print(f'{name} ({compression}) done', file=sys.stderr, flush=True)
            executor.shutdown()
    finally:
        bridge.terminate()
        try:
            bridge.wait(10)
        except subprocess.TimeoutExpired:
            bridge.kill()
    facts = machine_facts()
    print(f"{facts['nproc']} CPUs, {facts['cpu']}, Python {facts['python']}, zenoh {facts['eclipse-zenoh']}")
    print(table(['case: path', 'msg/s', 'p50 ms', 'p90 ms', 'p99 ms', 'received'], rows))
    return 0


if __name__ == '__main__':
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--quick', action='store_true', help='2 s per phase instead of 5 s')
    parser.add_argument('--publish', nargs=3, metavar=('CASE', 'RATE', 'SECONDS'), help=argparse.SUPPRESS)
    options = parser.parse_args()
    if options.publish:
        publish(options.publish[0], float(options.publish[1]), float(options.publish[2]))
        sys.exit(0)
    sys.exit(main(options))
