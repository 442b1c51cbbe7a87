"""cmd_vel latency across a bad link while big messages fill it, with and without zros.priority
(issue 36). Run through `sudo python benchmarks/link.py --part priority`.

The namespaces and shaper of benchmarks/link.py (30 ms +- 5 ms one way, 2 Mbit/s): the laptop
runs `zros router` and two publishers, as separate processes as teleop and map_server are:
`/cmd_vel` (TwistStamped at 10 Hz, stamped with the wall clock when sent) and a bulk stream
that fills the link (a 384x384 `/map`, transient local, at 1 Hz and a 1 MB `/camera/image_raw`
at 1 Hz, both reliable). The robot, a client of the router, subscribes to all three and records
each cmd_vel's one-way latency (both namespaces share one clock). Three phases of `--seconds`:
no bulk stream; bulk with every topic at Zenoh's default priority (`ZROS_TOPIC_PRIORITY=/*=data`);
bulk with zros's defaults (cmd_vel real_time + express, map and image data_low).
"""
from __future__ import annotations

import argparse
import json
import statistics
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
if str(REPO) not in sys.path:
    sys.path.insert(0, str(REPO))

from tools.link_netns import ROBOT_CONNECT, Topology  # noqa: E402
from tools.link_shaper import control  # noqa: E402

CLIENT = str(REPO / 'configs' / 'zenoh' / 'client.json5')
WITHOUT = '/*=data'            # every topic at Zenoh's default priority, nothing express
PHASES = (('no bulk stream', None, ''), ('bulk, no priorities', 'bulk', WITHOUT), ('bulk, zros priorities', 'bulk', ''))
IMAGE_BYTES = 640 * 512 * 3    # 0.98 MB, rgb8


# -- the roles, each its own process in a namespace ---------------------------------------------
def send_commands(seconds: float) -> None:
    """Teleop's part: TwistStamped on /cmd_vel at 10 Hz, header.stamp = wall time at sending."""
    import zros
    from zros.node import Node

    from interfaces.geometry_msgs.msg import TwistStamped

    zros.init([])
    node = Node('prio_teleop')
    publisher = node.create_publisher(TwistStamped, '/cmd_vel', 10)
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        msg = TwistStamped()
        now = time.time()
        msg.header.stamp.sec, msg.header.stamp.nanosec = int(now), int((now % 1) * 1e9)
        msg.twist.angular.z = 0.5
        publisher.publish(msg)
        time.sleep(0.1)
    zros.shutdown()


def send_bulk(seconds: float) -> None:
    """map_server's and a camera's part: a 384x384 map and a 1 MB image, each once a second."""
    import numpy as np

    import zros
    from zros.node import Node
    from zros.qos import DurabilityPolicy, QoSProfile

    from interfaces.nav_msgs.msg import OccupancyGrid
    from interfaces.sensor_msgs.msg import Image

    zros.init([])
    node = Node('prio_bulk')
    maps = node.create_publisher(OccupancyGrid, '/map', QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL))
    images = node.create_publisher(Image, '/camera/image_raw', 1)
    grid = OccupancyGrid()
    grid.info.width = grid.info.height = 384
    grid.info.resolution = 0.05
    rng = np.random.default_rng(0)
    image = Image(height=512, width=640, encoding='rgb8', step=640 * 3)
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        started = time.monotonic()
        grid.data = rng.integers(-1, 101, 384 * 384, dtype=np.int8)    # changes each time: no compression luck
        maps.publish(grid)
        image.data = rng.integers(0, 256, IMAGE_BYTES, dtype=np.uint8)
        images.publish(image)          # reliable: blocks while Zenoh's queues are full
        time.sleep(max(0.0, 1.0 - (time.monotonic() - started)))
    zros.shutdown()


def receive(seconds: float, out: str) -> None:
    """The robot's part: the latency of each cmd_vel [s], and the bulk bytes that arrived."""
    import zros
    from zros.node import Node
    from zros.qos import DurabilityPolicy, QoSProfile

    from interfaces.geometry_msgs.msg import TwistStamped
    from interfaces.nav_msgs.msg import OccupancyGrid
    from interfaces.sensor_msgs.msg import Image

    zros.init([])
    node = Node('prio_robot')
    latencies: list[tuple[float, float]] = []
    bulk = {'map': 0, 'image': 0, 'bytes': 0}

    def on_cmd(msg: TwistStamped) -> None:
        now = time.time()
        latencies.append((now, now - (msg.header.stamp.sec + msg.header.stamp.nanosec * 1e-9)))

    def counter(kind: str):
        def on_bulk(data: bytes) -> None:
            bulk[kind] += 1
            bulk['bytes'] += len(data)
        return on_bulk
    node.create_subscription(TwistStamped, '/cmd_vel', on_cmd, 100)
    node.create_subscription(OccupancyGrid, '/map', counter('map'),
                             QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL), raw=True)
    node.create_subscription(Image, '/camera/image_raw', counter('image'), 10, raw=True)
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        zros.spin_once(node, timeout_sec=0.1)
    Path(out).write_text(json.dumps({'latencies': latencies, 'bulk': bulk, 'seconds': seconds}))
    zros.shutdown()


# -- the benchmark --------------------------------------------------------------------------
def summary(latencies: list[float]) -> dict:
    """Median, 99th percentile and worst of one phase's latencies [s] (None when empty)."""
    if not latencies:
        return {'n': 0, 'median_s': None, 'p99_s': None, 'max_s': None}
    ordered = sorted(latencies)
    return {'n': len(ordered), 'median_s': statistics.median(ordered),
            'p99_s': ordered[min(len(ordered) - 1, int(0.99 * len(ordered)))], 'max_s': ordered[-1]}


def run(args: argparse.Namespace, env, wait) -> dict:
    """The three phases in one topology; `env(**extra)` and `wait(what, predicate, timeout)` are
    benchmarks/link.py's."""
    import os
    import tempfile
    logs = Path(tempfile.mkdtemp(prefix='link-priority-'))
    sock = str(logs / 'link.sock')
    me = [sys.executable, str(Path(__file__).resolve())]
    warmup = 5.0
    result: dict = {'settings': {'latency_ms': 30, 'jitter_ms': 5, 'rate_mbit_s': 2, 'seconds': args.seconds,
                                 'image_bytes': IMAGE_BYTES, 'map_cells': 384 * 384}, 'phases': {}}
    with Topology(logs) as topo:
        topo.start_shaper(Path(sock), '--latency', '0.03', '--jitter', '0.005', '--rate', '2e6')
        wait('shaper', lambda: os.path.exists(sock), 15)
        router = [sys.executable, '-m', 'zros.cli.main', 'router']
        if args.sndbuf:
            config = logs / 'router.json5'
            config.write_text(json.dumps({'transport': {'link': {'tcp': {'so_sndbuf': args.sndbuf}}}}))
            router += ['--config', str(config)]
            result['settings']['router_so_sndbuf'] = args.sndbuf
        topo.spawn(topo.laptop, router, 'router', env(), REPO)
        time.sleep(2.0)
        robot_env = env(ZROS_CONFIG=CLIENT, ZROS_CONNECT=ROBOT_CONNECT)
        for index, (name, bulk, rule) in enumerate(PHASES):
            out = logs / f'phase{index}.json'
            span = warmup + args.seconds
            receiver = topo.spawn(topo.robot, [*me, '--role', 'receive', str(span + 3.0), str(out)],
                                  f'receive{index}', robot_env, REPO)
            time.sleep(3.0)          # the robot's session and subscriptions across the link
            senders = [topo.spawn(topo.laptop, [*me, '--role', 'commands', str(span)], f'commands{index}',
                                  env(ZROS_TOPIC_PRIORITY=rule), REPO)]
            if bulk:
                senders.append(topo.spawn(topo.laptop, [*me, '--role', 'bulk', str(span)], f'bulk{index}',
                                          env(ZROS_TOPIC_PRIORITY=rule), REPO))
            started = time.time()
            time.sleep(warmup)
            first = control(sock, cmd='stats')
            receiver.wait(timeout=span + 60)
            last = control(sock, cmd='stats')
            for proc in senders:
                topo.stop(proc)
            data = json.loads(out.read_text()) if out.exists() else {'latencies': [], 'bulk': {}}
            kept = [lat for at, lat in data['latencies'] if at >= started + warmup]
            span_s = last['time'] - first['time']
            result['phases'][name] = {**summary(kept), 'bulk': data['bulk'],
                                      'link_to_robot_B_s': (last['down_bytes'] - first['down_bytes']) / span_s}
            time.sleep(args.drain)   # what the link still holds drains before the next phase
        result['logs'] = str(logs)
    return result


def table(r: dict) -> str:
    rows = ['| Phase (laptop -> robot, 30 ms +- 5 ms, 2 Mbit/s) | cmd_vel received | median | p99 | worst | '
            'bulk received (maps / images) | link to the robot |', '|---|---|---|---|---|---|---|']

    def ms(value: float | None) -> str:
        return 'n/a' if value is None else f'{value * 1e3:.0f} ms'
    for name, p in r['phases'].items():
        bulk = p['bulk']
        rows.append(f"| {name} | {p['n']} | {ms(p['median_s'])} | {ms(p['p99_s'])} | {ms(p['max_s'])} | "
                    f"{bulk.get('map', 0)} / {bulk.get('image', 0)} ({bulk.get('bytes', 0) / 1e6:.1f} MB) | "
                    f"{p['link_to_robot_B_s'] * 8e-6:.2f} Mbit/s |")
    return '\n'.join(rows)


def role(argv: list[str]) -> None:
    """Run one role: `commands SECONDS`, `bulk SECONDS` or `receive SECONDS OUT`."""
    try:
        if argv[0] == 'commands':
            send_commands(float(argv[1]))
        elif argv[0] == 'bulk':
            send_bulk(float(argv[1]))
        else:
            receive(float(argv[1]), argv[2])
    except KeyboardInterrupt:
        pass


if __name__ == '__main__':
    if sys.argv[1:2] == ['--role']:
        role(sys.argv[2:])
    else:
        sys.exit('run it as: sudo python benchmarks/link.py --part priority')
