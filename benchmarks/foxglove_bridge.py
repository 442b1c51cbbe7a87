"""foxglove_bridge against a direct zros subscription: messages per second and latency, same run.

    python benchmarks/foxglove_bridge.py            # about 40 s
    python benchmarks/foxglove_bridge.py --quick    # about 20 s: shorter windows

One publisher process sends stamped messages (header.stamp = the wall clock at publish). Two
receivers take the same stream at the same time:

- **direct**: a zros subscription in this process;
- **bridge**: `zros run foxglove_bridge foxglove_bridge` in its own process, and a Foxglove
  client made of Foxglove's npm packages (tests/data/foxglove_client.js, run by node) that
  decodes every message with the advertised schema.

Latency is receive time minus header.stamp (same machine, same clock), median and p90. Cases:
`geometry_msgs/PointStamped` at 100 Hz, a 360-ray `sensor_msgs/LaserScan` at 20 Hz, and a
throughput case (PointStamped published as fast as one Python process can) where msg/s is what
each receiver got per second of the window. The bridge's queue drops the oldest messages of a
client that falls behind (message_backlog_size), so its losses are counted, not waited for.

Needs node and npm, and the npm packages that tests/integration/test_foxglove_bridge.py installs into
~/.cache/zros-test-npm. Everything stays on loopback, in a free domain.
"""
from __future__ import annotations

import argparse
import json
import os
import re
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(REPO), str(Path(__file__).resolve().parent)]

from pubsub import machine_facts, percentile, pick_domain, table, worker_env  # noqa: E402

CLIENT = REPO / 'tests' / 'data' / 'foxglove_client.js'
NODE_MODULES = Path.home() / '.cache' / 'zros-test-npm' / 'node_modules'

# Publishes TYPE ('point' or 'scan') on /bench at RATE Hz (0: as fast as it can) for DURATION s,
# stamping each message with the wall clock, after waiting for 2 subscribers.
PUBLISHER = '''
import sys, time, zros
from zros.node import Node
from interfaces.geometry_msgs.msg import PointStamped
from interfaces.sensor_msgs.msg import LaserScan
kind, rate, duration = sys.argv[1], float(sys.argv[2]), float(sys.argv[3])
with zros.init():
    node = Node('bench_source')
    msg_type = PointStamped if kind == 'point' else LaserScan
    pub = node.create_publisher(msg_type, '/bench', 10)
    msg = msg_type()
    if kind == 'scan':
        msg.ranges = [1.0] * 360
        msg.intensities = [0.0] * 360
    deadline = time.monotonic() + 30
    while pub.get_subscription_count() < 2 and time.monotonic() < deadline:
        time.sleep(0.05)
    time.sleep(1.0)
    print('publishing', flush=True)
    start = time.monotonic()
    sent = 0
    while time.monotonic() - start < duration:
        now = time.time_ns()
        msg.header.stamp.sec, msg.header.stamp.nanosec = divmod(now, 1_000_000_000)
        pub.publish(msg)
        sent += 1
        if rate > 0:
            time.sleep(max(0.0, start + sent / rate - time.monotonic()))
    print(f'sent {sent}', flush=True)
'''


def run_case(group, url: str, kind: str, rate: float, window: float) -> dict:
    """One case: both receivers on one publisher; their counts and latencies [ms]."""
    from zros.executors import SingleThreadedExecutor
    from zros.node import Node
    from interfaces.geometry_msgs.msg import PointStamped
    from interfaces.sensor_msgs.msg import LaserScan
    msg_type = PointStamped if kind == 'point' else LaserScan
    direct: list[float] = []
    node = Node('bench_direct')

    def on_message(msg) -> None:
        stamp = msg.header.stamp.sec * 1_000_000_000 + msg.header.stamp.nanosec
        direct.append((time.time_ns() - stamp) / 1e6)
    node.create_subscription(msg_type, '/bench', on_message, 10)
    executor = SingleThreadedExecutor()
    executor.add_node(node)
    spinner = threading.Thread(target=executor.spin, daemon=True)
    spinner.start()
    plan = {'url': url, 'subscribe': ['/bench'], 'stamps': True, 'timeoutMs': int((window + 8) * 1000)}
    client = subprocess.Popen(['node', str(CLIENT), json.dumps(plan)], stdout=subprocess.PIPE, text=True,
                              env={'NODE_PATH': str(NODE_MODULES), 'PATH': '/usr/bin:/bin'})
    source = group.script(PUBLISHER, kind, str(rate), str(window), name=f'source_{kind}')
    try:
        source.wait_for_output('publishing', timeout=40)
        sent = int(re.search(r'sent (\d+)', source.wait_for_output('sent ', timeout=window + 30)).group(1))
        out, _ = client.communicate(timeout=window + 30)
    finally:
        if client.poll() is None:
            client.kill()
        executor.shutdown(timeout_sec=2)
        node.destroy_node()
        source.kill()
    bridged = [(e['recvNs'] - e['stampNs']) / 1e6 for e in map(json.loads, out.splitlines())
               if e.get('event') == 'stamp']
    return {'sent': sent, 'direct': direct, 'bridge': bridged, 'window': window}


def summarize(label: str, result: dict) -> list[list[str]]:
    rows = []
    for receiver in ('direct', 'bridge'):
        latencies = sorted(result[receiver])
        if not latencies:
            rows.append([label, receiver, str(result['sent']), '0', '-', '-', '-'])
            continue
        rows.append([label, receiver, str(result['sent']), str(len(latencies)),
                     f"{len(latencies) / result['window']:.0f}",
                     f'{percentile(latencies, 50):.2f}', f'{percentile(latencies, 90):.2f}'])
    return rows


def main(quick: bool) -> int:
    import zros
    from zros.testing import ProcessGroup
    if not (NODE_MODULES / '@foxglove' / 'rosmsg2-serialization').is_dir():
        print(f'no npm packages in {NODE_MODULES}: run tests/integration/test_foxglove_bridge.py once', file=sys.stderr)
        return 1
    domain = pick_domain()
    os.environ.update(worker_env(domain))
    window = 4.0 if quick else 10.0
    cases = [('PointStamped @ 100 Hz', 'point', 100.0), ('LaserScan 360 @ 20 Hz', 'scan', 20.0),
             ('PointStamped flat out', 'point', 0.0)]
    with tempfile.TemporaryDirectory() as logs:
        group = ProcessGroup(Path(logs), cwd=REPO)
        try:
            bridge = group.run('foxglove_bridge', 'foxglove_bridge', '--ros-args', '-p', 'address:=127.0.0.1',
                               '-p', 'port:=0')
            line = bridge.wait_for_output('listening on ws://', timeout=30)
            url = 'ws://127.0.0.1:' + re.search(r'ws://[\d.]+:(\d+)', bridge.output() + line).group(1)
            rows = []
            with zros.init(args=[]):
                for label, kind, rate in cases:
                    rows += summarize(label, run_case(group, url, kind, rate, window))
        finally:
            group.close()
    facts = machine_facts()
    print(f"{facts['nproc']} CPUs, {facts['cpu']}, Python {facts['python']}, load average "
          f"{os.getloadavg()[0]:.1f}")
    print(table(['case', 'receiver', 'sent', 'received', 'msg/s', 'p50 ms', 'p90 ms'], rows))
    return 0


if __name__ == '__main__':
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--quick', action='store_true', help='4 s windows instead of 10 s')
    sys.exit(main(parser.parse_args().quick))
