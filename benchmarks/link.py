"""The TurtleBot3 stack across a bad link (issue 36): bytes per topic, the stop after a drop-out,
and how soon the laptop sees the robot's nodes again.

    sudo python benchmarks/link.py               # about 3 minutes; needs root (network namespaces)
    sudo python benchmarks/link.py --view        # with the view (rviz2's role) open on the laptop
    sudo python benchmarks/link.py --json out.json
    sudo python benchmarks/link.py --part priority   # cmd_vel behind big messages (benchmarks/link_priority.py)

The robot and the laptop are tools/link_netns.py's namespaces, joined only through
tools/link_shaper.py at 30 ms one way, 5 ms jitter, 2 Mbit/s. The laptop runs `zros router` and
`turtlebot3_bringup laptop.launch.py` (map_server + AMCL and Nav2's servers); the robot runs
`turtlebot3_bringup robot.launch.py` (gzserver with cmd_vel_timeout 0.5 s, robot_state_publisher)
as a client of the laptop's router (configs/zenoh/client.json5), as docs/multi-machine.md says.

What is measured:
- `link`: the bytes per second through the shaper, each way, for `--seconds` s once the stack
  is up: what the whole stack costs on the link (Zenoh's framing included), nothing added.
- `per topic`: afterwards, a probe on the laptop subscribes to every topic and counts the
  serialized payload bytes and messages per second of each (its own subscriptions add traffic,
  so this window is not the one above).
- `stop`: teleop from the laptop (cmd_vel turning in place at 10 Hz); the link is dropped for
  `--drop` s (connections held, as Wi-Fi does), `--stops` times. The stop is read from
  gzserver's log line when its cmd_vel watchdog fires (simulated time, to the 5 ms physics step,
  and the line's wall stamp) against the drop's time; the last movement in the 30 Hz ground
  truth, which arrives when the link returns, is kept as a cross-check. Goal: <= 0.5 s. The
  watchdog fires 0.5 s after the last cmd_vel that got through, so with teleop at 10 Hz the
  stop falls 0.4-0.5 s after the drop, plus the error of placing the drop in simulated time.
- `graph`: after a drop-out that resets the connections (and one that holds them), the time from
  the link's return until `zros node list` on the laptop shows /gazebo and
  /robot_state_publisher. Goal: <= 2 s.
Navigation success over the link and the 30-minute soak are not measured yet (issue 36).
"""
from __future__ import annotations

import argparse
import json
import math
import os
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
if str(REPO) not in sys.path:
    sys.path.insert(0, str(REPO))

from tools.link_netns import ROBOT_CONNECT, Topology, unavailable_reason  # noqa: E402
from tools.link_shaper import control  # noqa: E402

GOALS = {'stop_s': 0.5, 'graph_s': 2.0, 'link_bit_s': 2e6}
ROBOT_NODES = ('/gazebo', '/robot_state_publisher')
CLIENT = str(REPO / 'configs' / 'zenoh' / 'client.json5')


def _env(**extra: str) -> dict[str, str]:
    env = {k: v for k, v in os.environ.items() if not k.startswith(('ZROS_', 'ROS_', 'ZENOH_'))}
    # no shared memory: the namespaces share this host's /dev/shm, and Zenoh would hand payloads of
    # 3 KB and up across it instead of over the link (a robot and a laptop share no memory)
    env.update(PYTHONUNBUFFERED='1', ZROS_DOMAIN_ID='0', TURTLEBOT3_MODEL='burger', ZROS_SHM_POOL_SIZE='0', **extra)
    return env


def _zros(topo: Topology, ns: str, *args: str, timeout: float = 30.0, **env: str) -> str:
    argv = ['ip', 'netns', 'exec', ns, sys.executable, '-m', 'zros.cli.main', *args]
    try:
        return subprocess.run(argv, capture_output=True, text=True, timeout=timeout, env=_env(**env),
                              cwd=REPO).stdout
    except subprocess.TimeoutExpired:
        return ''


def _wait(what: str, predicate, timeout: float) -> float:
    start = time.monotonic()
    while not predicate():
        if time.monotonic() - start > timeout:
            raise SystemExit(f'link benchmark: no {what} within {timeout:.0f} s')
        time.sleep(0.2)
    return time.monotonic() - start


# -- the probe, run inside the laptop's namespace -----------------------------------------------
def probe(seconds: float, topics_out: str) -> None:
    """Count payload bytes and messages per topic for `seconds`; write JSON to `topics_out`.
    With `--truth`, record the robot's ground truth instead (stamp, x, y) until killed."""
    import zros
    from zros.node import Node
    from zros.typesupport import get_message

    zros.init([])
    node = Node('link_probe')
    time.sleep(2.0)
    counts: dict[str, list[int]] = {}
    for name, types in node.get_topic_names_and_types():
        if name.startswith('/link_probe') or not types:
            continue
        counts[name] = [0, 0]
        try:
            node.create_subscription(get_message(types[0]), name,
                                     lambda data, c=counts[name]: c.__setitem__(slice(0, 2), [c[0] + 1, c[1] + len(data)]),
                                     100, raw=True)
        except Exception:
            counts.pop(name)
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        zros.spin_once(node, timeout_sec=0.1)
    Path(topics_out).write_text(json.dumps({k: [n / seconds, b / seconds] for k, (n, b) in counts.items()}))


def truth(out: str) -> None:
    """Append `sim_time x y yaw` of every /sim/ground_truth sample to `out` (the stop measurement)."""
    import zros
    from zros.node import Node

    from interfaces.nav_msgs.msg import Odometry

    zros.init([])
    node = Node('link_truth')
    with open(out, 'a', buffering=1) as file:
        def on_truth(msg: Odometry) -> None:
            p, q = msg.pose.pose.position, msg.pose.pose.orientation
            yaw = 2.0 * math.atan2(q.z, q.w)
            file.write(f'{msg.header.stamp.sec + msg.header.stamp.nanosec * 1e-9:.4f} {p.x:.5f} {p.y:.5f} {yaw:.5f}\n')
        node.create_subscription(Odometry, '/sim/ground_truth', on_truth, 1000)
        zros.spin(node)


def clock_now(out: str) -> None:
    """Keep writing the latest /clock and the wall time it arrived to `out` (one line, replaced)."""
    import zros
    from zros.node import Node

    from interfaces.rosgraph_msgs.msg import Clock

    zros.init([])
    node = Node('link_clock')

    def on_clock(msg: Clock) -> None:
        Path(out + '.new').write_text(f'{time.time():.4f} {msg.clock.sec + msg.clock.nanosec * 1e-9:.4f}')
        os.replace(out + '.new', out)   # a reader never sees it half written
    node.create_subscription(Clock, '/clock', on_clock, 10)
    zros.spin(node)


# -- the benchmark ------------------------------------------------------------------------------
def _sim_clock(clock_file: Path):
    """wall time -> simulated time, from two readings of --clock's file a second apart (the
    simulation may run slower than real time), each one latency (30 ms) old. Read it while the
    link is up: during a drop-out the file stands still."""
    (w1, s1) = map(float, clock_file.read_text().split())
    time.sleep(1.0)
    (w2, s2) = map(float, clock_file.read_text().split())
    rate = (s2 - s1) / (w2 - w1) if w2 > w1 else 1.0
    return lambda wall: s2 + (wall - w2 + 0.03) * rate


def _watchdog_stops(robot_log: Path) -> list[tuple[float, float]]:
    """(wall time of its log line, simulated time) of each stop by gzserver's cmd_vel watchdog."""
    text = robot_log.read_text(errors='replace') if robot_log.exists() else ''
    return [(float(wall), float(sim)) for wall, sim in re.findall(
        r'\[(\d+\.\d+)\] \[gazebo\]: \S+ stopped: no cmd_vel for [\d.]+ s \(cmd_vel_timeout\) at ([\d.]+) s', text)]


def _last_movement(lines: list[str], start: float, end: float) -> float | None:
    """Simulated time of the last sample in [start, end] that moved (> 1 mm or > 0.002 rad) from
    the one before it; None if none did."""
    samples = [tuple(map(float, line.split())) for line in lines if len(line.split()) == 4]
    last = None
    for (_, x0, y0, a0), (t1, x1, y1, a1) in zip(samples, samples[1:]):
        turned = abs(math.remainder(a1 - a0, math.tau))
        if start <= t1 <= end and (math.hypot(x1 - x0, y1 - y0) > 1e-3 or turned > 2e-3):
            last = t1
    return last


def run(args: argparse.Namespace) -> dict:
    logs = Path(tempfile.mkdtemp(prefix='link-bench-'))
    sock = str(logs / 'link.sock')
    me = [sys.executable, str(Path(__file__).resolve())]
    result: dict = {'settings': {'latency_ms': 30, 'jitter_ms': 5, 'rate_mbit_s': 2, 'view': args.view,
                                 'drop_s': args.drop}}
    with Topology(logs) as topo:
        topo.start_shaper(Path(sock), '--latency', '0.03', '--jitter', '0.005', '--rate', '2e6')
        _wait('shaper', lambda: os.path.exists(sock), 15)
        zros = [sys.executable, '-m', 'zros.cli.main']
        topo.spawn(topo.laptop, [*zros, 'router'], 'router', _env(), REPO)
        time.sleep(2.0)
        topo.spawn(topo.laptop, [*zros, 'launch', 'turtlebot3_bringup', 'laptop.launch.py',
                                 f'view:={"true" if args.view else "false"}'], 'laptop', _env(), REPO)
        topo.spawn(topo.robot, [*zros, 'launch', 'turtlebot3_bringup', 'robot.launch.py'], 'robot',
                   _env(ZROS_CONFIG=CLIENT, ZROS_CONNECT=ROBOT_CONNECT), REPO)

        def stack_up() -> bool:
            nodes = _zros(topo, topo.laptop, 'node', 'list').split()
            return all(n in nodes for n in (*ROBOT_NODES, '/amcl', '/controller_server', '/bt_navigator'))
        result['startup_s'] = _wait('stack (robot and laptop nodes in the graph)', stack_up, 240)
        # where the robot starts (robot.launch.py's pose), as a user gives it in RViz: AMCL then
        # publishes map -> odom, and the costmaps and the pose flow as they do in a real session
        _zros(topo, topo.laptop, 'topic', 'pub', '--once', '/initialpose',
              'geometry_msgs/msg/PoseWithCovarianceStamped',
              '{header: {frame_id: map}, pose: {pose: {position: {x: -2.0, y: -0.5}, orientation: {w: 1.0}}}}')
        time.sleep(5.0)

        # the whole stack on the link, nothing added
        first = control(sock, cmd='stats')
        time.sleep(args.seconds)
        last = control(sock, cmd='stats')
        span = last['time'] - first['time']
        result['link'] = {'robot_to_laptop_B_s': (last['up_bytes'] - first['up_bytes']) / span,
                          'laptop_to_robot_B_s': (last['down_bytes'] - first['down_bytes']) / span}

        # per topic, by a probe on the laptop
        per_topic = logs / 'topics.json'
        p = topo.spawn(topo.laptop, [*me, '--probe', str(args.seconds), str(per_topic)], 'probe', _env(), REPO)
        p.wait(timeout=args.seconds + 60)
        result['topics'] = json.loads(per_topic.read_text()) if per_topic.exists() else {}

        # stop time: teleop, then a held drop-out
        truth_file, clock_file = logs / 'truth.txt', logs / 'clock.txt'
        topo.spawn(topo.laptop, [*me, '--truth', str(truth_file)], 'truth', _env(), REPO)
        topo.spawn(topo.laptop, [*me, '--clock', str(clock_file)], 'clock', _env(), REPO)
        turn = '{angular: {z: 0.5}}'      # in place: nothing to bump into whatever the pose
        teleop = topo.spawn(topo.laptop, [*zros, 'topic', 'pub', '-r', '10', '/cmd_vel', 'geometry_msgs/msg/Twist',
                                          turn], 'teleop', _env(), REPO)
        _wait('ground truth and clock on the laptop',
              lambda: truth_file.exists() and clock_file.exists() and truth_file.stat().st_size > 1000, 60)
        result['stops'] = []
        for _ in range(args.stops):
            time.sleep(1.0)
            sim_at = _sim_clock(clock_file)
            moving = _last_movement(truth_file.read_text().splitlines(), sim_at(time.time()) - 1.0,
                                    math.inf) is not None
            control(sock, cmd='drop', seconds=args.drop)
            dropped = time.time()
            sim_at_drop = sim_at(dropped)
            time.sleep(args.drop + 3.0)
            lines = truth_file.read_text().splitlines()
            moved = _last_movement(lines, sim_at_drop - 1.0, sim_at_drop + args.drop - 0.2)
            fired = [(w, t) for w, t in _watchdog_stops(topo.logs / 'robot.log') if dropped - 1.0 <= w <= dropped + args.drop]
            result['stops'].append({
                'moving_before': moving,
                'stop_after_drop_s': None if moved is None else moved - sim_at_drop,           # 30 Hz ground truth
                'watchdog_after_drop_s': fired[0][1] - sim_at_drop if fired else None,       # simulated, to the step
                'watchdog_wall_after_drop_s': fired[0][0] - dropped if fired else None,      # its log line's wall stamp
                'truth_samples_after_drop': sum(1 for t in lines if float(t.split()[0]) > sim_at_drop)})
        topo.stop(teleop)
        result['stop'] = result['stops'][0]

        # graph after the link returns: held and reset drop-outs. Each `zros node list` is a new
        # process that takes its own start-up time, so the attempts are kept: (started after
        # the return [s], took [s], listed the robot's nodes)
        result['graph'], result['graph_attempts'] = {}, {}
        started = time.monotonic()
        listed = all(n in _zros(topo, topo.laptop, 'node', 'list').split() for n in ROBOT_NODES)
        result['graph_baseline_s'] = time.monotonic() - started if listed else None   # the command alone
        for mode in ('hold', 'reset'):
            control(sock, cmd='set', dropout_mode=mode)
            control(sock, cmd='drop', seconds=args.drop)
            back = time.monotonic() + args.drop
            time.sleep(args.drop)
            while time.monotonic() < back:
                time.sleep(0.01)
            attempts: list[tuple[float, float, bool]] = []
            while time.monotonic() - back < 30 and not (attempts and attempts[-1][2]):
                started = time.monotonic()
                nodes = _zros(topo, topo.laptop, 'node', 'list', timeout=10).split()
                attempts.append((started - back, time.monotonic() - started, all(n in nodes for n in ROBOT_NODES)))
            result['graph_attempts'][mode] = attempts
            result['graph'][mode] = time.monotonic() - back if attempts[-1][2] else None
        control(sock, cmd='set', dropout_mode='hold')
        result['logs'] = str(logs)
    return result


def table(r: dict) -> str:
    link = r['link']
    total = (link['robot_to_laptop_B_s'] + link['laptop_to_robot_B_s']) * 8
    rows = ['| Measure | Value | Goal |', '|---|---|---|',
            f"| robot -> laptop, whole stack | {link['robot_to_laptop_B_s'] / 1e3:.1f} kB/s | |",
            f"| laptop -> robot, whole stack | {link['laptop_to_robot_B_s'] / 1e3:.1f} kB/s | |",
            f"| both ways | {total / 1e6:.2f} Mbit/s | <= 2 Mbit/s |"]
    def listing(values: list) -> str:
        return ', '.join('n/a' if v is None else f'{v:.3f}' for v in values) + ' s'
    rows.append(f"| robot stops after the link drops: gzserver's watchdog (to the 5 ms step) | "
                f"{listing([s['watchdog_after_drop_s'] for s in r['stops']])} | <= 0.5 s |")
    rows.append(f"| the same in wall time (the log line's stamp; both namespaces share the clock) | "
                f"{listing([s['watchdog_wall_after_drop_s'] for s in r['stops']])} | |")
    rows.append(f"| the same from 30 Hz ground truth (last movement) | "
                f"{listing([s['stop_after_drop_s'] for s in r['stops']])} | |")
    for mode, seconds in r['graph'].items():
        tries = r['graph_attempts'][mode]
        detail = ', '.join(f"{'yes' if ok else 'no'} at {t0:.1f}+{took:.1f} s" for t0, took, ok in tries)
        rows.append(f"| robot's nodes in `zros node list` after a {mode} drop-out | "
                    f"{'not within 30 s' if seconds is None else f'{seconds:.1f} s'} ({detail}) | <= 2 s |")
    base = r.get('graph_baseline_s')
    rows.append(f"| `zros node list` on the laptop with the link up (the command alone) | "
                f"{'did not list them' if base is None else f'{base:.1f} s'} | |")
    rows += ['', '| Topic (payload, probe on the laptop) | msg/s | kB/s |', '|---|---|---|']
    for name, (rate, bps) in sorted(r['topics'].items(), key=lambda kv: -kv[1][1]):
        if rate > 0:
            rows.append(f'| `{name}` | {rate:.1f} | {bps / 1e3:.2f} |')
    return '\n'.join(rows)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--seconds', type=float, default=20.0, help='measurement window [s]')
    parser.add_argument('--drop', type=float, default=5.0, help='drop-out length [s]')
    parser.add_argument('--view', action='store_true', help='open the view on the laptop')
    parser.add_argument('--stops', type=int, default=1, help='drop-outs for the stop measurement')
    parser.add_argument('--json', help='also write the results here')
    parser.add_argument('--part', choices=('stack', 'priority'), default='stack',
                        help='stack: the TurtleBot3 stack (the default); priority: cmd_vel latency behind '
                             'big messages, with and without priorities (benchmarks/link_priority.py)')
    parser.add_argument('--drain', type=float, default=15.0, help=argparse.SUPPRESS)
    parser.add_argument('--sndbuf', type=int, default=0,
                        help="--part priority: the laptop router's TCP send buffer (Zenoh's "
                             'transport/link/tcp/so_sndbuf) [bytes]; 0: the kernel\'s')
    parser.add_argument('--probe', nargs=2, metavar=('SECONDS', 'OUT'), help=argparse.SUPPRESS)
    parser.add_argument('--truth', metavar='OUT', help=argparse.SUPPRESS)
    parser.add_argument('--clock', metavar='OUT', help=argparse.SUPPRESS)
    args = parser.parse_args()
    try:
        if args.probe:
            probe(float(args.probe[0]), args.probe[1])
            return 0
        if args.truth:
            truth(args.truth)
            return 0
        if args.clock:
            clock_now(args.clock)
            return 0
    except KeyboardInterrupt:
        return 0
    reason = unavailable_reason()
    if reason:
        print(f'link benchmark: {reason}', file=sys.stderr)
        return 1
    if args.part == 'priority':
        import link_priority
        result = link_priority.run(args, _env, _wait)
        print(link_priority.table(result))
    else:
        result = run(args)
        print(table(result))
    if args.json:
        Path(args.json).write_text(json.dumps(result, indent=2))
    return 0


if __name__ == '__main__':
    sys.exit(main())
