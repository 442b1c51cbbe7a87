"""Simulator benchmark: how fast the TurtleBot3 simulation runs, what a lidar scan costs, and what
the simulator node costs at real time.

    python benchmarks/sim.py            # about 90 s
    python benchmarks/sim.py --quick    # about 35 s
    python benchmarks/sim.py --json out.json
    python benchmarks/sim.py --gazebo-world /tmp/tb3/turtlebot3_gazebo/worlds/turtlebot3_world.world   # + its load time

Goals (issue 15, docs/architecture.md §9; issue 33): the headless simulation with the lidar on runs at
>= 20x real time on one core in every shipped world (the house and the bighouse too); a 360-beam scan
costs < 1 ms; a world file, SDF and mesh ones too, loads in < 2 s; the simulator at 1x takes < 10% of a core.

What is measured, in one run:
- `load`: a fresh Python's CPU time up to a loaded world (`load_world`, interpreter start and
  imports included, as gzserver starts; CPU time, so a busy machine does not inflate it), and
  its wall time, for each shipped YAML world, its SDF twin in turtlebot3_gazebo/worlds, and any
  `--gazebo-world` (a Gazebo world of your own, e.g. ROBOTIS's with meshes: set GAZEBO_MODEL_PATH
  to its models folder); the median of 3 runs.
- `lidar`: median time of one 360-beam scan (`SimRobot.scan()`: ray casting plus noise) from 200
  poses spread over the free space of turtlebot3_world, turtlebot3_house and turtlebot3_bighouse.
- `headless`: zros.sim's Simulation alone (no Zenoh): one burger driving a fixed tour of changing
  commands, bumping into things, with what the node does every simulated second (200 steps, 5
  scans, 30 odometry reads, 200 IMU reads). The real-time factor is simulated time over this
  thread's CPU time (`time.thread_time`), i.e. on one core whatever else the machine does, and
  also over wall time.
- `node, as fast as possible`: `zros run turtlebot3_gazebo gzserver` with real_time_factor 0
  and turtlebot3_world, publishing everything (clock, scan, odom, tf, joint_states, imu, ground
  truth) with one subscriber process reading scan, odom, tf and imu. The factor is simulated
  time (from /clock) over the node's CPU time (utime + stime from /proc) and over wall time.
- `node at 1x`: the same at real_time_factor 1 for `--seconds` s: the node's CPU time over
  wall time, in % of one core.
Each measurement of a process uses a domain id from 201 upwards whose hub port is free.
"""
from __future__ import annotations

import argparse
import json
import math
import os
import platform
import signal
import statistics
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[1]
sys.path[:0] = [p for p in (str(REPO), str(Path(__file__).resolve().parent)) if p not in sys.path]

from pubsub import pick_domain  # noqa: E402

CLK_TCK = os.sysconf('SC_CLK_TCK')

GOALS = {'rtf_headless': 20.0, 'lidar_ms': 1.0, 'cpu_1x_percent': 10.0, 'load_s': 2.0}
WORLDS = ('turtlebot3_world', 'turtlebot3_house', 'turtlebot3_bighouse')
SDF_WORLDS = REPO / 'nodes' / 'turtlebot3_gazebo' / 'worlds'
_LOAD = '''
import sys, time
start = time.perf_counter()
from zros.sim import load_world
world = load_world(sys.argv[1], on_warning=lambda message: None)
print(time.process_time(), time.perf_counter() - start, len(world.edges), len(world.circles))
'''


def bench_load(worlds: list[str], runs: int = 3) -> dict:
    """CPU and wall seconds from a fresh interpreter to each loaded world (medians of `runs`)."""
    results = {}
    for world in worlds:
        cpu, wall = [], []
        for _ in range(runs):
            out = subprocess.run([sys.executable, '-c', _LOAD, world], capture_output=True, text=True, cwd=REPO,
                                 timeout=120, check=True).stdout.split()
            cpu.append(float(out[0]))
            wall.append(float(out[1]))
        results[world] = {'seconds': statistics.median(cpu), 'wall_seconds': statistics.median(wall),
                          'edges': int(out[2]), 'circles': int(out[3])}
    return results


def _world_label(world: str) -> str:
    path = Path(world)
    if not path.suffix:
        return world
    return f'{path.name} (shipped)' if path.parent == SDF_WORLDS else f'{path.name} (given)'


# -- the library, in this process ------------------------------------------------------------
def bench_lidar(scans: int) -> dict:
    from zros.sim import Simulation, load_world
    results = {}
    rng = np.random.default_rng(0)
    for name in WORLDS:
        world = load_world(name)
        sim = Simulation(world)
        robot = sim.add_robot('burger')
        xmin, ymin, xmax, ymax = world.bounds()
        poses = []
        while len(poses) < 200:
            x, y = rng.uniform(xmin, xmax), rng.uniform(ymin, ymax)
            if not world.collides(x, y, 0.12):
                poses.append((x, y, rng.uniform(-math.pi, math.pi)))
        times = []
        for k in range(scans):
            if k % (scans // len(poses)) == 0:
                sim.teleport('burger', poses[(k * len(poses)) // scans])
            start = time.perf_counter()
            robot.scan()
            times.append(time.perf_counter() - start)
        results[name] = statistics.median(times) * 1e3
    return results


def bench_headless(sim_seconds: float) -> dict:
    from zros.sim import Simulation, load_world
    results = {}
    for name in WORLDS:
        sim = Simulation(load_world(name), seed=1)
        robot = sim.add_robot('burger')
        steps = int(round(sim_seconds / sim.dt))
        wall0, cpu0 = time.perf_counter(), time.thread_time()
        for step in range(steps):
            if step % 100 == 0:        # a new command every 0.5 s
                k = step // 100
                robot.command(0.22 * math.cos(0.3 * k), 1.5 * math.sin(0.7 * k))
            sim.step()
            robot.imu()
            if step % 7 == 0:          # ~30 Hz odometry
                robot.odometry()
            if step % 40 == 0:         # 5 Hz lidar
                robot.scan()
        cpu, wall = time.thread_time() - cpu0, time.perf_counter() - wall0
        results[name] = {'rtf_cpu': sim_seconds / cpu, 'rtf_wall': sim_seconds / wall,
                         'collisions': robot.collisions}
    return results


# -- the node, as processes ------------------------------------------------------------------------
def _cpu_seconds(pid: int) -> float:
    fields = Path(f'/proc/{pid}/stat').read_text().rsplit(')', 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / CLK_TCK


_SUBSCRIBER = '''
import sys, zros
from zros.node import Node
from zros.qos import QoSProfile
from interfaces.sensor_msgs.msg import LaserScan, Imu
from interfaces.nav_msgs.msg import Odometry
from interfaces.tf2_msgs.msg import TFMessage
with zros.init():
    node = Node('bench_reader')
    for t, topic in ((LaserScan, '/scan'), (Odometry, '/odom'), (TFMessage, '/tf'), (Imu, '/imu')):
        node.create_subscription(t, topic, lambda m: None, 10)
    print('ready', flush=True)
    try:
        zros.spin(node)
    except KeyboardInterrupt:
        pass
'''


def bench_node(rtf: float, seconds: float) -> dict:
    """Run gzserver at `rtf` for `seconds` of wall time; its CPU use and the simulated time."""
    from zros.context import Context
    from zros.node import Node
    from interfaces.rosgraph_msgs.msg import Clock
    domain = pick_domain()
    env = dict(os.environ, ZROS_DOMAIN_ID=str(domain), TURTLEBOT3_MODEL='burger')
    for name in ('ZROS_CONNECT', 'ZROS_DISCOVERY', 'ZROS_CONFIG'):
        env.pop(name, None)
    server = subprocess.Popen([sys.executable, '-m', 'zros', 'run', 'turtlebot3_gazebo', 'gzserver', '--ros-args',
                               '-p', 'world:=turtlebot3_world', '-p', f'real_time_factor:={rtf}'],
                              stdout=subprocess.PIPE, stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL, env=env,
                              cwd=REPO, start_new_session=True)
    reader = subprocess.Popen([sys.executable, '-c', _SUBSCRIBER], stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                              stdin=subprocess.DEVNULL, env=env, cwd=REPO, start_new_session=True)
    os.environ['ZROS_DOMAIN_ID'] = str(domain)
    context = Context().init([], install_signal_handlers=False)
    try:
        node = Node('bench_clock', context=context)
        latest = [0]
        node.create_subscription(Clock, '/clock',
                                 lambda m: latest.__setitem__(0, m.clock.sec * 10**9 + m.clock.nanosec), 10)
        from zros.executors import SingleThreadedExecutor
        executor = SingleThreadedExecutor(context=context)
        executor.add_node(node)

        def spin_for(duration: float) -> None:
            end = time.monotonic() + duration
            while time.monotonic() < end:
                executor.spin_once(timeout_sec=0.05)
        deadline = time.monotonic() + 60
        while latest[0] == 0:
            if time.monotonic() > deadline or server.poll() is not None:
                raise RuntimeError('gzserver did not start publishing /clock')
            spin_for(0.1)
        spin_for(2.0)                          # warm up: subscriber matched, caches filled
        sim0, cpu0, wall0 = latest[0], _cpu_seconds(server.pid), time.monotonic()
        spin_for(seconds)
        sim1, cpu1, wall1 = latest[0], _cpu_seconds(server.pid), time.monotonic()
    finally:
        context.shutdown()
        for proc in (server, reader):
            try:
                os.killpg(proc.pid, signal.SIGKILL)
            except (ProcessLookupError, PermissionError):
                pass
            proc.wait(timeout=10)
    sim_s, cpu_s, wall_s = (sim1 - sim0) / 1e9, cpu1 - cpu0, wall1 - wall0
    return {'rtf': rtf, 'sim_s': sim_s, 'cpu_s': cpu_s, 'wall_s': wall_s,
            'rtf_wall': sim_s / wall_s, 'rtf_cpu': sim_s / cpu_s if cpu_s else math.inf,
            'cpu_percent': 100.0 * cpu_s / wall_s}


def _mark(value: float, goal: float, higher_is_better: bool) -> str:
    return 'PASS' if (value >= goal if higher_is_better else value < goal) else 'MISS'


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--quick', action='store_true', help='shorter runs (about 35 s)')
    parser.add_argument('--seconds', type=float, default=None, help='wall seconds per node measurement')
    parser.add_argument('--json', metavar='FILE', help='also write the results as JSON')
    parser.add_argument('--gazebo-world', action='append', default=[], metavar='FILE',
                        help='also time loading this Gazebo world file (repeatable)')
    parser.add_argument('--no-node', action='store_true', help='skip the node measurements (library only)')
    args = parser.parse_args()
    if not sys.platform.startswith('linux'):
        print('this benchmark reads /proc and runs on Linux only', file=sys.stderr)
        return 1
    seconds = args.seconds or (8.0 if args.quick else 20.0)
    load = bench_load([*WORLDS, *(str(SDF_WORLDS / f'{name}.world') for name in WORLDS), *args.gazebo_world])
    lidar = bench_lidar(1000 if args.quick else 4000)
    headless = bench_headless(60.0 if args.quick else 300.0)
    fast = real = None
    if not args.no_node:
        fast = bench_node(0.0, seconds)
        real = bench_node(1.0, seconds)

    print(f'\nzros simulator benchmark (turtlebot3_gazebo / zros.sim), {platform.machine()}, '
          f'{os.cpu_count()} CPUs, Python {platform.python_version()}, load average {os.getloadavg()[0]:.2f}\n')
    rows = []
    for world, r in load.items():
        rows.append((f'load {_world_label(world)}: {r["edges"]} edges, {r["circles"]} circles, CPU',
                     f"{r['seconds']:.2f} s", '< 2 s', _mark(r['seconds'], GOALS['load_s'], False)))
        rows.append(('  (same, wall time)', f"{r['wall_seconds']:.2f} s", '', ''))
    rows += [(f'lidar scan, {name} (median)', f'{ms:.3f} ms', '< 1 ms', _mark(ms, GOALS['lidar_ms'], False))
             for name, ms in lidar.items()]
    for name, r in headless.items():
        rows.append((f'headless sim + lidar, {name}, one core', f"{r['rtf_cpu']:.0f}x", '>= 20x',
                     _mark(r['rtf_cpu'], GOALS['rtf_headless'], True)))
        rows.append(('  (same, over wall time)', f"{r['rtf_wall']:.0f}x", '', ''))
    if fast is not None and real is not None:
        rows.append(('node, as fast as possible, per core of CPU', f"{fast['rtf_cpu']:.1f}x", '>= 20x',
                     _mark(fast['rtf_cpu'], GOALS['rtf_headless'], True)))
        rows.append(('  (same, over wall time)', f"{fast['rtf_wall']:.1f}x", '', ''))
        rows.append(('node at real_time_factor 1: CPU', f"{real['cpu_percent']:.1f} % of a core", '< 10 %',
                     _mark(real['cpu_percent'], GOALS['cpu_1x_percent'], False)))
        rows.append(('  (achieved real-time factor)', f"{real['rtf_wall']:.3f}x", '1x', ''))
    width = max(len(r[0]) for r in rows)
    print(f"| {'measure':<{width}} | {'result':>16} | {'goal':>7} |      |")
    print(f"|{'-' * (width + 2)}|{'-' * 18}|{'-' * 9}|------|")
    for label, value, goal, mark in rows:
        print(f'| {label:<{width}} | {value:>16} | {goal:>7} | {mark:<4} |')
    if args.json:
        Path(args.json).write_text(json.dumps({'load': load, 'lidar_ms': lidar, 'headless': headless, 'node_fast': fast,
                                               'node_1x': real}, indent=2))
    return 0


if __name__ == '__main__':
    sys.exit(main())
