"""The TurtleBot3 stack across a bad link (issue 36): bytes per topic, the stop after a drop-out,
and how soon the laptop sees the robot's nodes again.

    sudo python benchmarks/link.py               # about 3 minutes; needs root (network namespaces)
    sudo python benchmarks/link.py --view        # with the view (rviz2's role) open on the laptop
    sudo python benchmarks/link.py --json out.json
    sudo python benchmarks/link.py --part priority   # cmd_vel behind big messages (benchmarks/link_priority.py)
    sudo python benchmarks/link.py --part relist --stops 3   # the graph and teleop after drop-outs

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
- `--part relist` (instead of the above): the same after `--stops` drop-outs of each kind, and a
  teleop running on the laptop all along (a node publishing cmd_vel at 10 Hz while its key is
  held) whose key is pressed the moment the link returns: the time until the robot's /odom, as
  the laptop receives it, turns.

    sudo python benchmarks/link.py --navigate 20  # 20 goals with drop-outs, about 10 minutes
    sudo python benchmarks/link.py --soak 30      # 30 minutes of goals: memory, graph, lost messages

`--navigate N` (instead of the measurements above): BasicNavigator, as a user's mission script
on the laptop, drives N seeded goals in turtlebot3_world (benchmarks/navigation.py's draw: free
cells >= 0.2 m from any obstacle, reachable on the map) while the link drops for `--drop` s
every `--period` s. A goal ends as Nav2 says (SUCCEEDED, or FAILED with its error code), or is
canceled when it has run 3 x (path length / 0.22 m/s) + 30 s of simulated time. A goal whose
attempt failed while or shortly after (`RETRY_GRACE_S`) the link was down is sent again, up to
`RETRIES` times, as a mission does: first-try and with-retry figures are both reported.
Collisions: the simulator's contact count (/sim/collisions). Goals: >= 95 % with retries, 0
collisions.

`--soak MINUTES`: the same for MINUTES of wall time, with a reliable probe topic from the robot
(tests/multihost/seqnode.py at 20 Hz) and: the RSS and PSS of every process in both namespaces
at the start, after the warm-up (a sixth of the run, at most 5 minutes) and at the end (goal:
<= 10 % growth after the warm-up); the graph's entities (liveliness tokens) the laptop sees at
the start, after the warm-up and at the end (goal: equal after the warm-up: the servers create some
on their first goal; nothing leaked); the probe's missing sequence numbers
(goal: 0).
"""
from __future__ import annotations

import argparse
import collections
import json
import math
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Callable, Iterator

REPO = Path(__file__).resolve().parents[1]
if str(REPO) not in sys.path:
    sys.path.insert(0, str(REPO))

from tools.link_netns import ROBOT_CONNECT, Topology, unavailable_reason  # noqa: E402
from tools.link_shaper import control  # noqa: E402

GOALS = {'stop_s': 0.5, 'graph_s': 2.0, 'link_bit_s': 2e6}
RETRIES = 2               # a mission sends a goal the link's loss failed again, this many times
RETRY_GRACE_S = 10.0      # [s] after the link returns, a failure still counts as the drop-out's
START_POSE = (-2.0, -0.5)  # robot.launch.py's spawn pose, in the map frame
SEQ_NODE = REPO / 'tests' / 'multihost' / 'seqnode.py'
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


def truth(out: str, topic: str = '/sim/ground_truth', wall: bool = False) -> None:
    """Append `time x y yaw` of every Odometry sample on `topic` to `out`: the message's simulated
    stamp (the stop measurement), or with `wall` the wall time it arrived on the laptop (teleop
    after a drop-out, `--part relist`)."""
    import zros
    from zros.node import Node

    from interfaces.nav_msgs.msg import Odometry

    zros.init([])
    node = Node('link_truth')
    with open(out, 'a', buffering=1) as file:
        def on_truth(msg: Odometry) -> None:
            p, q = msg.pose.pose.position, msg.pose.pose.orientation
            yaw = 2.0 * math.atan2(q.z, q.w)
            stamp = time.time() if wall else msg.header.stamp.sec + msg.header.stamp.nanosec * 1e-9
            file.write(f'{stamp:.4f} {p.x:.5f} {p.y:.5f} {yaw:.5f}\n')
        node.create_subscription(Odometry, topic, on_truth, 1000)
        zros.spin(node)


def teleop(control_file: str) -> None:
    """A teleop that is running all along, as a user's teleop_twist_keyboard: while
    `control_file` holds a non-zero turn rate [rad/s] (a key held down), publish it on /cmd_vel
    at 10 Hz; nothing otherwise."""
    import zros
    from zros.node import Node

    from interfaces.geometry_msgs.msg import Twist

    zros.init([])
    node = Node('link_teleop')
    publisher = node.create_publisher(Twist, '/cmd_vel', 10)

    def tick() -> None:
        try:
            rate = float(Path(control_file).read_text() or 0.0)
        except (OSError, ValueError):
            rate = 0.0
        if rate:
            msg = Twist()
            msg.angular.z = rate
            publisher.publish(msg)
    node.create_timer(0.1, tick)
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


# -- navigation over the link: the bookkeeping ---------------------------------------------------
def failed_by_drop(start: float, end: float, drops: list[tuple[float, float]], grace: float = RETRY_GRACE_S) -> bool:
    """Whether an attempt that ran from `start` to `end` (wall time) met a drop-out: one of
    `drops` (start, end) began before the attempt ended and ended less than `grace` s before it
    started (localization and the costmaps take a few seconds to catch up on the backlog)."""
    return any(d0 <= end and d1 + grace >= start for d0, d1 in drops)


def goal_summary(goals: list[list[dict]]) -> dict:
    """Figures of a mission from each goal's attempts (dicts with `outcome` and `sim_s`, in order):
    goals reached at the first try and with the retries, and the simulated time of each
    reached goal, all of its attempts included."""
    reached = [g for g in goals if g and g[-1]['outcome'] == 'succeeded']
    times = [sum(a['sim_s'] for a in g) for g in reached]
    return {'goals': len(goals),
            'first_try': sum(1 for g in goals if g and g[0]['outcome'] == 'succeeded'),
            'with_retry': len(reached),
            'retried': sum(1 for g in goals if len(g) > 1),
            'met_drop': sum(1 for g in goals if any(a.get('drop') for a in g)),
            'goal_s_median': statistics.median(times) if times else math.nan,
            'goal_s_max': max(times) if times else math.nan}


def memory_growth(samples: dict[str, list[int]]) -> dict[str, float]:
    """Growth of each process's memory from the second sample (after the warm-up) to the last,
    as a fraction of the second: {label: (last - warm) / warm}, for processes sampled each time."""
    return {label: (kib[-1] - kib[1]) / kib[1] for label, kib in samples.items() if len(kib) >= 3 and kib[1] > 0}


def missing_sequence(seqs: list[int]) -> int:
    """How many numbers are missing between the first and the last of a stream that counts
    1, 2, 3, ... (repeats and late ones are not missing)."""
    if not seqs:
        return 0
    return max(seqs) - min(seqs) + 1 - len(set(seqs))


def link_goals(count: int, seed: int) -> Iterator[tuple[tuple[float, float, float], float]]:
    """`count` seeded goals (drawn as they are asked for) in turtlebot3_world on turtlebot3_navigation2's map (the laptop's),
    each reachable from the one before (the first from the spawn pose), and its ideal time
    [s]: the planned path's length at the burger's 0.22 m/s."""
    import numpy as np

    from benchmarks.navigation import MAX_SPEED, draw_goal, goal_candidates, stack_parameters
    from zros.ament_index_python.packages import get_package_share_directory
    from zros.map_io import load_map
    from zros.navigation.costmap import LayeredCostmap
    from zros.navigation.planner import GridPlanner
    from zros.sim import load_world

    grid = load_map(Path(get_package_share_directory('turtlebot3_navigation2')) / 'map' / 'map.yaml')
    costmap = LayeredCostmap(stack_parameters()[1])
    costmap.set_static_map(grid.data, grid.resolution, tuple(grid.origin[:2]))
    costmap.update()
    planner = GridPlanner(costmap)
    candidates = goal_candidates(load_world('turtlebot3_world'), grid)
    rng = np.random.default_rng(seed)
    at = START_POSE
    for _ in range(count):
        goal, path = draw_goal(rng, candidates, lambda xy: planner.plan(at, xy))
        yield goal, float(np.linalg.norm(np.diff(path, axis=0), axis=1).sum()) / MAX_SPEED
        at = goal[:2]


def _process_memory(namespaces: list[str]) -> dict[str, tuple[int, int]]:
    """(RSS, PSS) in KiB of every process in `namespaces`, by `pid command`."""
    from benchmarks.launch import _memory_kib
    from tools.link_netns import ip

    table = {}
    for ns in namespaces:
        for pid in ip('netns', 'pids', ns, check=False).split():
            try:
                argv = Path(f'/proc/{pid}/cmdline').read_bytes().split(b'\0')
                label = ' '.join(a.decode(errors='replace').rsplit('/', 1)[-1] for a in argv[:6] if a)
                table[f'{pid} {label}'] = _memory_kib(int(pid))
            except (OSError, AttributeError, ValueError):
                continue                                    # gone meanwhile
    return table


# -- the mission, run inside the laptop's namespace ----------------------------------------------
def mission(config_path: str) -> None:
    """BasicNavigator driving the goals of `config` (JSON: out, sock, goals, seed, seconds, drop,
    period; optional max_drops, and modes: the shaper's dropout_mode of each drop-out in turn,
    'hold' by default) while a thread drops the link every `period` s; writes the attempts, the drop-outs,
    the collisions and the graph's size at the start and the end to `out`."""
    import threading

    import zros
    from zros.graph import fetch_entities
    from zros.nav2_simple_commander.robot_navigator import BasicNavigator, TaskResult
    from zros.qos import DurabilityPolicy, QoSProfile

    from interfaces.geometry_msgs.msg import PoseStamped
    from interfaces.rosgraph_msgs.msg import Clock
    from interfaces.std_msgs.msg import UInt32

    config = json.loads(Path(config_path).read_text())
    context = zros.init([])
    navigator = BasicNavigator()
    state = {'clock': 0.0, 'collisions': None}
    navigator.create_subscription(Clock, '/clock',
                                  lambda m: state.__setitem__('clock', m.clock.sec + m.clock.nanosec / 1e9), 10)
    navigator.create_subscription(UInt32, 'sim/collisions', lambda m: state.__setitem__('collisions', m.data),
                                  QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL))

    def pose(x: float, y: float, yaw: float = 0.0) -> PoseStamped:
        p = PoseStamped()
        p.header.frame_id = 'map'
        p.header.stamp = navigator.get_clock().now().to_msg()
        p.pose.position.x, p.pose.position.y = x, y
        p.pose.orientation.z, p.pose.orientation.w = math.sin(yaw / 2), math.cos(yaw / 2)
        return p

    navigator.setInitialPose(pose(*START_POSE))
    if not navigator.waitUntilNav2Active(timeout=300):
        raise SystemExit('link mission: Nav2 did not come up within 300 s')
    while state['collisions'] is None:
        zros.spin_once(navigator, timeout_sec=0.2)
    own = str(context.session.info.zid())

    def entities() -> dict[str, int]:
        """The graph's entities (liveliness tokens) as `node kind name`: count, this process's own left out."""
        return dict(collections.Counter(f'{e.node_fqn} {e.kind} {e.name}'.rstrip()
                                        for e in fetch_entities(context.session, context.domain_id, 3.0) if e.zid != own))
    out: dict = {'entities_start': entities(),
                 'collisions_start': state['collisions'], 'drops': [], 'goals': []}
    stop = threading.Event()

    def dropper() -> None:
        modes = config.get('modes', ['hold'])
        while not stop.wait(config['period']) and len(out['drops']) < config.get('max_drops', math.inf):
            control(config['sock'], cmd='set', dropout_mode=modes[len(out['drops']) % len(modes)])
            control(config['sock'], cmd='drop', seconds=config['drop'])
            now = time.time()
            out['drops'].append((now, now + config['drop']))
    threading.Thread(target=dropper, daemon=True).start()
    began = time.monotonic()
    for (x, y, yaw), ideal in link_goals(config['goals'], config['seed']):
        if time.monotonic() - began > config['seconds']:
            break
        attempts: list[dict] = []
        out['goals'].append({'goal': (x, y, yaw), 'ideal_s': ideal, 'attempts': attempts})
        while len(attempts) <= RETRIES:
            start, sim0 = time.time(), state['clock']
            navigator.goToPose(pose(x, y, yaw))
            budget = 3 * ideal + 30.0
            timed_out = False
            while not timed_out and not navigator.isTaskComplete():
                if state['clock'] - sim0 > budget or time.time() - start > 4 * budget + 60:
                    navigator.cancelTask()
                    timed_out = True
            result = navigator.getResult()
            outcome = 'timed out' if timed_out else 'succeeded' if result == TaskResult.SUCCEEDED else result.name.lower()
            end = time.time()
            attempts.append({'outcome': outcome, 'sim_s': state['clock'] - sim0, 'wall': (start, end),
                             'drop': failed_by_drop(start, end, list(out['drops']))})
            print(f'goal {len(out["goals"])} ({x:.2f}, {y:.2f}) try {len(attempts)}: {outcome} in '
                  f'{attempts[-1]["sim_s"]:.1f} s sim{" (the link dropped)" if attempts[-1]["drop"] else ""}',
                  flush=True)
            if outcome == 'succeeded' or not attempts[-1]['drop']:
                break
        if 'entities_warm' not in out and time.monotonic() - began >= config.get('warmup', 0.0):
            out['entities_warm'] = entities()      # after a goal: servers create some entities on their first
        out['collisions_end'] = state['collisions']
        Path(config['out']).write_text(json.dumps(out, indent=1))     # so far: a mission that hangs still tells
    stop.set()
    time.sleep(config['drop'] + 3.0)                     # the last drop-out over, the graph whole again
    zros.spin_once(navigator, timeout_sec=0.5)
    out['collisions_end'] = state['collisions']
    out['entities_end'] = entities()
    Path(config['out']).write_text(json.dumps(out, indent=1))
    navigator.destroy_node()
    zros.shutdown()


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


def _movements(lines: list[str], start: float, end: float) -> list[float]:
    """Times of the samples in [start, end] that moved (> 1 mm or > 0.002 rad) from the one
    before them, in order."""
    samples = [tuple(map(float, line.split())) for line in lines if len(line.split()) == 4]
    moved = []
    for (_, x0, y0, a0), (t1, x1, y1, a1) in zip(samples, samples[1:]):
        turned = abs(math.remainder(a1 - a0, math.tau))
        if start <= t1 <= end and (math.hypot(x1 - x0, y1 - y0) > 1e-3 or turned > 2e-3):
            moved.append(t1)
    return moved


def _last_movement(lines: list[str], start: float, end: float) -> float | None:
    """Simulated time of the last sample in [start, end] that moved; None if none did."""
    moved = _movements(lines, start, end)
    return moved[-1] if moved else None


def _start_stack(topo: Topology, sock: str, view: bool, laptop_args: tuple[str, ...] = ()) -> float:
    """The shaper, the laptop's router and half of the stack (with `laptop_args`, launch
    arguments such as `params_file:=...`), the robot's half; the seconds until the laptop's
    graph has the robot's nodes and Nav2's."""
    topo.start_shaper(Path(sock), '--latency', '0.03', '--jitter', '0.005', '--rate', '2e6')
    _wait('shaper', lambda: os.path.exists(sock), 15)
    zros = [sys.executable, '-m', 'zros.cli.main']
    topo.spawn(topo.laptop, [*zros, 'router'], 'router', _env(), REPO)
    time.sleep(2.0)
    topo.spawn(topo.laptop, [*zros, 'launch', 'turtlebot3_bringup', 'laptop.launch.py',
                             f'view:={"true" if view else "false"}', *laptop_args], 'laptop', _env(), REPO)
    topo.spawn(topo.robot, [*zros, 'launch', 'turtlebot3_bringup', 'robot.launch.py'], 'robot',
               _env(ZROS_CONFIG=CLIENT, ZROS_CONNECT=ROBOT_CONNECT), REPO)

    def stack_up() -> bool:
        nodes = _zros(topo, topo.laptop, 'node', 'list').split()
        return all(n in nodes for n in (*ROBOT_NODES, '/amcl', '/controller_server', '/bt_navigator'))
    return _wait('stack (robot and laptop nodes in the graph)', stack_up, 240)


def run_navigate(args: argparse.Namespace, goals: int, seconds: float, soak: bool) -> dict:
    """The mission over the link (`--navigate`, `--soak`): up to `goals` goals for at most
    `seconds` of wall time; with `soak`, the probe topic and the memory samples as well."""
    logs = Path(tempfile.mkdtemp(prefix='link-nav-'))
    sock = str(logs / 'link.sock')
    me = [sys.executable, str(Path(__file__).resolve())]
    result: dict = {'settings': {'latency_ms': 30, 'jitter_ms': 5, 'rate_mbit_s': 2, 'drop_s': args.drop,
                                 'period_s': args.period, 'seed': args.seed}, 'logs': str(logs),
                    'load_start': os.getloadavg()[0]}
    with Topology(logs) as topo:
        result['startup_s'] = _start_stack(topo, sock, args.view)
        if soak:
            seq = [sys.executable, str(SEQ_NODE)]
            sub = topo.spawn(topo.laptop, [*seq, 'sub', 'link_seq_sub'], 'seq_sub', _env(), REPO)
            topo.spawn(topo.robot, [*seq, 'pub', 'link_seq_pub', '20'], 'seq_pub',
                       _env(ZROS_CONFIG=CLIENT, ZROS_CONNECT=ROBOT_CONNECT), REPO)
        config = logs / 'mission.json'
        config.write_text(json.dumps({'out': str(logs / 'mission-out.json'), 'sock': sock, 'goals': goals,
                                      'seed': args.seed, 'seconds': seconds, 'drop': args.drop,
                                      'period': args.period, 'warmup': min(300.0, seconds / 6)}))
        mission_proc = topo.spawn(topo.laptop, [*me, '--mission', str(config)], 'mission', _env(), REPO)
        memory: dict[str, list[tuple[int, int]]] = {}

        def sample_memory() -> None:
            for label, kib in _process_memory([topo.robot, topo.laptop]).items():
                memory.setdefault(label, []).append(kib)
        started = time.monotonic()
        if soak:
            sample_memory()                                 # the start
            while mission_proc.poll() is None and time.monotonic() - started < min(300.0, seconds / 6):
                time.sleep(1.0)
            sample_memory()                                 # after the warm-up
        try:
            mission_proc.wait(timeout=None if math.isinf(seconds) else seconds + 600)
        except subprocess.TimeoutExpired:
            result['mission_hung'] = True               # what it wrote after its last goal stands
        if soak:
            sample_memory()                                 # the end, the stack still up
            topo.stop(mission_proc)
            seqs = [int(n) for n in re.findall(r'^got (\d+)$', sub.log.read_text(errors='replace'), re.M)]
            result['probe'] = {'received': len(seqs), 'missing': missing_sequence(seqs)}
            ours = {label: kib for label, kib in memory.items() if 'link.py' not in label and 'seqnode' not in label}
            result['memory_kib'] = ours
            result['rss_growth'] = memory_growth({k: [r for r, _ in v] for k, v in ours.items()})
            result['pss_growth'] = memory_growth({k: [p for _, p in v] for k, v in ours.items()})
        out = logs / 'mission-out.json'
        if not out.exists():
            raise SystemExit(f'link benchmark: the mission failed; see {mission_proc.log}')
        result['mission'] = json.loads(out.read_text())
        result['wall_s'] = time.monotonic() - started
        result['load_end'] = os.getloadavg()[0]
    return result


def run(args: argparse.Namespace) -> dict:
    logs = Path(tempfile.mkdtemp(prefix='link-bench-'))
    sock = str(logs / 'link.sock')
    me = [sys.executable, str(Path(__file__).resolve())]
    result: dict = {'settings': {'latency_ms': 30, 'jitter_ms': 5, 'rate_mbit_s': 2, 'view': args.view,
                                 'drop_s': args.drop}}
    with Topology(logs) as topo:
        zros = [sys.executable, '-m', 'zros.cli.main']
        result['startup_s'] = _start_stack(topo, sock, args.view, tuple(args.laptop_arg))
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

        # graph after the link returns: held and reset drop-outs
        result['graph'], result['graph_attempts'] = {}, {}
        result['graph_baseline_s'] = _baseline_listing(topo)
        for mode in ('hold', 'reset'):
            result['graph'][mode], result['graph_attempts'][mode] = _relist(topo, sock, mode, args.drop)
        control(sock, cmd='set', dropout_mode='hold')
        result['logs'] = str(logs)
    return result


def _baseline_listing(topo: Topology) -> float | None:
    """How long one `zros node list` on the laptop takes with the link up (the command alone);
    None if it did not list the robot's nodes."""
    started = time.monotonic()
    listed = all(n in _zros(topo, topo.laptop, 'node', 'list').split() for n in ROBOT_NODES)
    return time.monotonic() - started if listed else None


def _relist(topo: Topology, sock: str, mode: str, drop: float,
            at_return: Callable[[], None] | None = None) -> tuple[float | None, list[tuple[float, float, bool]]]:
    """Drop the link for `drop` s (`mode`: hold or reset the connections), then run `zros node
    list` on the laptop from the moment it returns until one lists the robot's nodes (30 s at
    most). Each listing is a new process with its own start-up, so every attempt is kept as
    (started after the return [s], took [s], listed the robot's nodes). Returns the seconds from
    the return to the end of the listing that had them (None: none in 30 s), and the attempts.
    `at_return` runs the moment the link is back, before the first listing."""
    control(sock, cmd='set', dropout_mode=mode)
    control(sock, cmd='drop', seconds=drop)
    back = time.monotonic() + drop
    time.sleep(drop)
    while time.monotonic() < back:
        time.sleep(0.01)
    if at_return is not None:
        at_return()
    attempts: list[tuple[float, float, bool]] = []
    while time.monotonic() - back < 30 and not (attempts and attempts[-1][2]):
        started = time.monotonic()
        nodes = _zros(topo, topo.laptop, 'node', 'list', timeout=10).split()
        attempts.append((started - back, time.monotonic() - started, all(n in nodes for n in ROBOT_NODES)))
    control(sock, cmd='set', dropout_mode='hold')
    return (time.monotonic() - back if attempts[-1][2] else None), attempts


def run_relist(args: argparse.Namespace) -> dict:
    """`--part relist`: after each drop-out (held, then reset, `--stops` times), how soon the
    laptop's `zros node list` shows the robot's nodes, and how soon a teleop that ran all along
    on the laptop turns the robot when its key is pressed at the return (the robot's /odom, as
    the laptop receives it, moves)."""
    logs = Path(tempfile.mkdtemp(prefix='link-relist-'))
    sock = str(logs / 'link.sock')
    me = [sys.executable, str(Path(__file__).resolve())]
    result: dict = {'settings': {'latency_ms': 30, 'jitter_ms': 5, 'rate_mbit_s': 2, 'view': args.view,
                                 'drop_s': args.drop}, 'logs': str(logs), 'load_start': os.getloadavg()[0]}
    with Topology(logs) as topo:
        result['startup_s'] = _start_stack(topo, sock, args.view)
        odom_file, key_file = logs / 'odom.txt', logs / 'teleop_key.txt'
        key_file.write_text('0')
        topo.spawn(topo.laptop, [*me, '--truth', str(odom_file), '--truth-topic', '/odom', '--wall'], 'odom',
                   _env(), REPO)
        topo.spawn(topo.laptop, [*me, '--teleop', str(key_file)], 'teleop', _env(), REPO)
        _wait('odometry on the laptop', lambda: odom_file.exists() and odom_file.stat().st_size > 1000, 60)
        result['graph_baseline_s'] = _baseline_listing(topo)
        result['returns'] = []
        for _ in range(args.stops):
            for mode in ('hold', 'reset'):
                def press() -> None:      # at the return: turn in place, nothing to bump into
                    key_file.write_text('0.5')
                    pressed.append(time.time())
                pressed: list[float] = []
                listed, attempts = _relist(topo, sock, mode, args.drop, at_return=press)
                moved = None                      # the first odometry sample that turned, as it arrived
                while moved is None and time.time() - pressed[0] < 15:
                    turned = _movements(odom_file.read_text().splitlines(), pressed[0], math.inf)
                    moved = turned[0] - pressed[0] if turned else None
                    time.sleep(0.05)
                key_file.write_text('0')
                time.sleep(2.0)                   # the watchdog stops the robot before the next drop
                result['returns'].append({'mode': mode, 'listed_s': listed, 'attempts': attempts,
                                          'teleop_moved_s': moved})
        result['load_end'] = os.getloadavg()[0]
    return result


def relist_table(r: dict) -> str:
    """`--part relist`'s figures as rows for docs/benchmarks.md."""
    rows = ['| After the link returns | Value | Goal |', '|---|---|---|']
    for mode in ('hold', 'reset'):
        mine = [x for x in r['returns'] if x['mode'] == mode]
        listed = ', '.join('n/a' if x['listed_s'] is None else f"{x['listed_s']:.2f}" for x in mine)
        tries = ', '.join(str(len(x['attempts'])) for x in mine)
        moved = ', '.join('n/a' if x['teleop_moved_s'] is None else f"{x['teleop_moved_s']:.2f}" for x in mine)
        rows.append(f"| {mode} drop-out: robot's nodes in `zros node list` (listings needed) | {listed} s ({tries}) | <= 2 s |")
        rows.append(f'| {mode} drop-out: teleop running all along, key pressed at the return, turns the robot '
                    f'(odom on the laptop) | {moved} s | |')
    base = r.get('graph_baseline_s')
    rows.append(f"| `zros node list` with the link up (the command alone) | "
                f"{'did not list them' if base is None else f'{base:.2f} s'} | |")
    rows.append(f"\n(load average {r['load_start']:.1f} -> {r['load_end']:.1f}; logs: {r['logs']})")
    return '\n'.join(rows)


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


def navigate_table(r: dict) -> str:
    """The mission's figures (and the soak's, when measured) as docs/benchmarks.md's rows."""
    m = r['mission']
    goals = [g['attempts'] for g in m['goals']]
    f = goal_summary(goals)
    n = max(1, f['goals'])
    collisions = m['collisions_end'] - m['collisions_start']
    failed = ', '.join(f"{a['outcome']}{' (drop)' if a['drop'] else ''}" for g in goals for a in g
                       if a['outcome'] != 'succeeded') or 'none'
    rows = ['| Measure | Value | Goal |', '|---|---|---|',
            f"| goals reached, first try | {f['first_try']} of {f['goals']} ({100 * f['first_try'] / n:.0f} %) | |",
            f"| goals reached, a goal the drop-out failed sent again | {f['with_retry']} of {f['goals']} "
            f"({100 * f['with_retry'] / n:.0f} %) | >= 95 % |",
            f"| collisions (the simulator's contacts) | {collisions} | 0 |",
            f"| sim time per reached goal, median / max | {f['goal_s_median']:.0f} / {f['goal_s_max']:.0f} s | |",
            f"| drop-outs ({r['settings']['drop_s']:g} s every {r['settings']['period_s']:g} s); goals the link "
            f"dropped under (or < {RETRY_GRACE_S:g} s before) | {len(m['drops'])}; {f['met_drop']} | |",
            f"| failed attempts | {failed} | |"]
    if 'probe' in r:
        rss, pss = r['rss_growth'], r['pss_growth']
        worst = max(rss, key=rss.get) if rss else 'none'
        start, warm, end = m['entities_start'], m.get('entities_warm', {}), m.get('entities_end', {})
        changed = ''.join(f", `{n}` {warm.get(n, 0)} -> {end.get(n, 0)}" for n in sorted(set(warm) | set(end))
                          if warm.get(n, 0) != end.get(n, 0))
        total = [sum(kib[i][0] for kib in r['memory_kib'].values() if len(kib) >= 3) / 1024 for i in range(3)]
        rows += [f"| RSS of the {len(rss)} processes at start / after warm-up / end | "
                 f"{total[0]:.0f} / {total[1]:.0f} / {total[2]:.0f} MiB | |",
                 f"| largest growth after the warm-up, RSS (PSS) | {100 * rss.get(worst, 0.0):+.1f} % "
                 f"({100 * pss.get(worst, 0.0):+.1f} %), `{worst.split(' ', 1)[-1]}` | <= 10 % |",
                 f"| graph entities (liveliness tokens) at start / after warm-up / end{changed} | "
                 f"{sum(start.values())} / {sum(warm.values())} / {sum(end.values())} | equal after warm-up |",
                 f"| reliable probe (20 Hz, robot -> laptop): received / missing | "
                 f"{r['probe']['received']} / {r['probe']['missing']} | 0 missing |"]
    if r.get('mission_hung'):
        rows.append('| the mission | hung in its last goal: stopped, its goals so far counted | |')
    rows.append(f"\n(wall {r['wall_s'] / 60:.0f} min, load average {r['load_start']:.1f} -> {r['load_end']:.1f}; "
                f"logs: {r['logs']})")
    return '\n'.join(rows)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--seconds', type=float, default=20.0, help='measurement window [s]')
    parser.add_argument('--drop', type=float, default=5.0, help='drop-out length [s]')
    parser.add_argument('--view', action='store_true', help='open the view on the laptop')
    parser.add_argument('--laptop-arg', action='append', default=[], metavar='NAME:=VALUE',
                        help='a launch argument for laptop.launch.py, e.g. params_file:=my_nav2.yaml (repeatable)')
    parser.add_argument('--stops', type=int, default=1, help='drop-outs for the stop measurement')
    parser.add_argument('--json', help='also write the results here')
    parser.add_argument('--part', choices=('stack', 'priority', 'relist'), default='stack',
                        help='stack: the TurtleBot3 stack (the default); priority: cmd_vel latency behind '
                             'big messages, with and without priorities (benchmarks/link_priority.py); '
                             'relist: the graph and teleop after drop-outs (--stops of each kind)')
    parser.add_argument('--drain', type=float, default=15.0, help=argparse.SUPPRESS)
    parser.add_argument('--sndbuf', type=int, default=0,
                        help="--part priority: the laptop router's TCP send buffer (Zenoh's "
                             'transport/link/tcp/so_sndbuf) [bytes]; 0: the kernel\'s')
    parser.add_argument('--navigate', type=int, metavar='GOALS', help='navigation over the link: GOALS goals')
    parser.add_argument('--soak', type=float, metavar='MINUTES', help='the soak: goals for MINUTES, memory and loss')
    parser.add_argument('--period', type=float, default=60.0, help='seconds between drop-outs (--navigate, --soak)')
    parser.add_argument('--seed', type=int, default=1, help='of the goals (--navigate, --soak)')
    parser.add_argument('--mission', metavar='CONFIG', help=argparse.SUPPRESS)
    parser.add_argument('--probe', nargs=2, metavar=('SECONDS', 'OUT'), help=argparse.SUPPRESS)
    parser.add_argument('--truth', metavar='OUT', help=argparse.SUPPRESS)
    parser.add_argument('--truth-topic', default='/sim/ground_truth', help=argparse.SUPPRESS)
    parser.add_argument('--wall', action='store_true', help=argparse.SUPPRESS)
    parser.add_argument('--clock', metavar='OUT', help=argparse.SUPPRESS)
    parser.add_argument('--teleop', metavar='KEY_FILE', help=argparse.SUPPRESS)
    args = parser.parse_args()
    try:
        if args.probe:
            probe(float(args.probe[0]), args.probe[1])
            return 0
        if args.truth:
            truth(args.truth, args.truth_topic, args.wall)
            return 0
        if args.clock:
            clock_now(args.clock)
            return 0
        if args.teleop:
            teleop(args.teleop)
            return 0
        if args.mission:
            mission(args.mission)
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
    elif args.part == 'relist':
        result = run_relist(args)
        print(relist_table(result))
    elif args.navigate is not None or args.soak is not None:
        if (args.navigate is not None and args.navigate < 1) or (args.soak is not None and args.soak <= 0):
            print('link benchmark: --navigate needs at least 1 goal, --soak more than 0 minutes', file=sys.stderr)
            return 1
        soak = args.soak is not None
        result = run_navigate(args, 10_000 if soak else args.navigate, args.soak * 60 if soak else math.inf, soak)
        print(navigate_table(result))
    else:
        result = run(args)
        print(table(result))
    if args.json:
        Path(args.json).write_text(json.dumps(result, indent=2))
    return 0


if __name__ == '__main__':
    sys.exit(main())
