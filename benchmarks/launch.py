"""Launch benchmark: how long `zros launch` takes to bring N nodes into the graph, what an idle
node costs in memory, and how long Ctrl-C takes to bring everything down.

    python benchmarks/launch.py                 # 20 talkers, 3 runs
    python benchmarks/launch.py --nodes 10 --runs 1
    python benchmarks/launch.py --load          # 50 and 100 nodes under load (issue 20)
    python benchmarks/launch.py --json out.json

Each run writes a launch file with N `demo_nodes/talker` nodes (distinct names `talker_00` ..),
starts `python -m zros launch FILE` in a fresh domain (from 201 up, first with a free hub port)
and measures, from just before the supervisor process is spawned:
- `started`: when the supervisor has reported `process started` for all N (its own overhead);
- `first` / `all`: when the first / all N node names are visible in the graph, read by this
  script with `zros.graph.fetch_entities` every 50 ms (this script connects only once the
  supervisor holds the hub port, so the launch is the hub, as on a fresh machine);
- `settled`: then, until the launch uses less than half a CPU over 2 s (every process has
  linked to every other and holds the whole graph);
- CPU of each node and of the supervisor once settled, over `CPU_WINDOW_S` (an idle talker
  publishes once a second; a listener of the pairs hears every talker and prints each message);
- memory of each node once settled:
  RSS and PSS from /proc/<pid>/smaps_rollup (PSS splits shared pages, such as the Python
  binary and the zenoh library, between the processes that map them), and the supervisor's;
- `shutdown`: from SIGINT to the supervisor until it and every node have exited, how much CPU
  the nodes used in that time, and how many processes the supervisor had to escalate to
  SIGTERM or SIGKILL.

`--load` runs 50 and 100 nodes, half `talker` and half `listener` (every listener hears every
talker), once each, and adds graph reads: `zros node list` and `zros topic list`, run as a user
runs them (a fresh process each time) `--graph-reads` times each while the launch is up, timed
wall-clock from spawn to exit, and checked for a complete answer (all N nodes, no "partial"
warning; a read still running after 60 s counts as 60 s and incomplete), with the CPU each
used, and the graph read alone from this script's open session (what the verbs cost beyond
starting an interpreter); then, over 10 s, how many listeners print every talker's messages
(a link Zenoh left half open silently loses one talker for one listener). Whether Python may
cache byte-code (PYTHONDONTWRITEBYTECODE unset, as users have it) changes what every process
costs to start: the header says which.
Goals (issue 20): every read under 1 s, Ctrl-C to everything gone under 3 s, no escalation.
`--nodes 50 100 --runs 1 --graph-reads 5` measures the same with talkers only: the graph's size
without the N x N message load of the pairs.
"""
from __future__ import annotations

import argparse
import json
import os
import platform
import re
import resource
import shutil
import signal
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path[:0] = [p for p in (str(REPO), str(Path(__file__).resolve().parent)) if p not in sys.path]

from pubsub import pick_domain  # noqa: E402
from zros.config import hub_port_free  # noqa: E402

TIMEOUT_S = 120.0   # plus 2 s per node: 100 interpreters start slowly on 2 CPUs
CPU_WINDOW_S = 5.0


def _node_names(nodes: int, pairs: bool) -> list[tuple[str, str]]:
    """(executable, node name) of each node: all talkers, or talkers and listeners alternating."""
    if not pairs:
        return [('talker', f'talker_{i:02d}') for i in range(nodes)]
    return [('talker', f'talker_{i // 2:02d}') if i % 2 == 0 else ('listener', f'listener_{i // 2:02d}')
            for i in range(nodes)]


def _launch_file(directory: Path, names: list[tuple[str, str]]) -> Path:
    lines = ['launch:']
    for executable, name in names:
        lines.append(f'- node: {{pkg: demo_nodes, exec: {executable}, name: {name}}}')
    path = directory / 'bench.launch.yaml'
    path.write_text('\n'.join(lines) + '\n')
    return path


def _machine_busy() -> tuple[float, float]:
    """(busy, total) CPU time of the whole machine so far, from /proc/stat (in ticks)."""
    values = [int(v) for v in Path('/proc/stat').read_text().split('\n', 1)[0].split()[1:]]
    idle = values[3] + values[4]    # idle + iowait
    return sum(values) - idle, sum(values)


#: How long the pairs' deliveries are counted, and the share of the talkers' messages a
#: listener must print in that time to count as hearing every talker (a 1 Hz timer's jitter).
DELIVERY_WINDOW_S = 10.0
DELIVERY_SHARE = 0.9


def _deliveries(out_path: Path, names: list[tuple[str, str]]) -> dict:
    """How many listeners hear every talker: each listener's `I heard` lines in the launch output
    over DELIVERY_WINDOW_S against the talkers' rate (1 Hz each). A link that Zenoh left half
    open shows here: its listener misses that talker's messages, with no error anywhere."""
    talkers = sum(1 for executable, _ in names if executable == 'talker')
    listeners = [name for executable, name in names if executable == 'listener']
    start = out_path.stat().st_size
    time.sleep(DELIVERY_WINDOW_S)
    with open(out_path, 'rb') as out:
        out.seek(start)
        text = out.read().decode(errors='replace')
    heard = {name: 0 for name in listeners}
    for name in re.findall(r'\[(listener_\d+)\]: I heard', text):
        if name in heard:
            heard[name] += 1
    rates = [count / DELIVERY_WINDOW_S for count in heard.values()]
    return {'listeners': len(listeners), 'hearing_all': sum(r >= DELIVERY_SHARE * talkers for r in rates),
            'heard_min_per_s': min(rates), 'talkers': talkers}


def _graph_reads(env: dict, expected: set[str], reads: int, session, domain: int, launch: list[int]) -> dict:
    """Wall time of `zros node list` / `zros topic list` as fresh processes (a read that has not
    exited after 60 s counts as 60 s, incomplete), whether each answer was complete, and the
    graph read alone, made from this process's open session; and how busy the machine was
    meanwhile, and with what: the load average trails a launch's start by minutes, while the
    share of the CPUs in use, and the launch's part of it, say what a command competed with."""
    from zros.graph import fetch_entities
    machine_before, launch_before, t0 = _machine_busy(), _cpu_seconds(launch), time.monotonic()
    times: dict[str, list[float]] = {'node': [], 'topic': []}
    cpu: list[float] = []
    in_process: list[float] = []
    loads: list[float] = []
    complete = 0
    for _ in range(reads):
        loads.append(os.getloadavg()[0])
        started = time.monotonic()
        fetch_entities(session, domain, timeout=1.0)
        in_process.append(time.monotonic() - started)
        for verb in ('node', 'topic'):
            before = resource.getrusage(resource.RUSAGE_CHILDREN)
            started = time.monotonic()
            try:
                done = subprocess.run([sys.executable, '-m', 'zros', verb, 'list'], capture_output=True, text=True,
                                      env=env, cwd=REPO, timeout=60)
            except subprocess.TimeoutExpired:
                done = None
            times[verb].append(time.monotonic() - started)
            after = resource.getrusage(resource.RUSAGE_CHILDREN)   # (the launch is reaped only at the end)
            cpu.append(after.ru_utime - before.ru_utime + after.ru_stime - before.ru_stime)
            if verb == 'node':
                complete += (done is not None and done.returncode == 0 and expected <= set(done.stdout.split())
                             and 'partial' not in done.stderr)
    machine_after, elapsed = _machine_busy(), time.monotonic() - t0
    return {'node_list_s': times['node'], 'topic_list_s': times['topic'], 'complete_reads': complete, 'cli_cpu_s': cpu,
            'read_in_process_s': in_process, 'load_during_reads': statistics.mean(loads),
            'machine_busy': (machine_after[0] - machine_before[0]) / max(1, machine_after[1] - machine_before[1]),
            'launch_cpus': (_cpu_seconds(launch) - launch_before) / elapsed}


def _memory_kib(pid: int) -> tuple[int, int]:
    """(RSS, PSS) in KiB of one process."""
    text = Path(f'/proc/{pid}/smaps_rollup').read_text()
    rss = int(re.search(r'^Rss:\s+(\d+) kB', text, re.M).group(1))
    pss = int(re.search(r'^Pss:\s+(\d+) kB', text, re.M).group(1))
    return rss, pss


def _cpu_of(pid: int) -> float | None:
    """User + system CPU time used so far by a process; None once it is gone."""
    try:
        fields = Path(f'/proc/{pid}/stat').read_text().rsplit(')', 1)[1].split()
    except (FileNotFoundError, ProcessLookupError):
        return None
    return (int(fields[11]) + int(fields[12])) / os.sysconf('SC_CLK_TCK')


def _cpu_seconds(pids: list[int]) -> float:
    """User + system CPU time used so far by these processes (those still alive)."""
    return sum(cpu for cpu in map(_cpu_of, pids) if cpu is not None)


def _cpu_shares(pids: list[int], supervisor: int) -> dict:
    """Each node's and the supervisor's CPU over `CPU_WINDOW_S`, as a share of one CPU."""
    before = {pid: _cpu_of(pid) or 0.0 for pid in [supervisor, *pids]}
    time.sleep(CPU_WINDOW_S)
    share = {pid: ((_cpu_of(pid) or before[pid]) - before[pid]) / CPU_WINDOW_S for pid in before}
    nodes = [share[pid] for pid in pids]
    return {'node_cpu_median': statistics.median(nodes), 'node_cpu_max': max(nodes), 'nodes_cpu_total': sum(nodes),
            'supervisor_cpu': share[supervisor]}


def _settle(pids: list[int], limit: float) -> float:
    """Seconds until the launch uses less than half a CPU over 2 s (it has finished starting:
    every process linked to every other and has the whole graph), at most `limit`."""
    started = time.monotonic()
    before = _cpu_seconds(pids)
    while time.monotonic() - started < limit:
        time.sleep(2.0)
        now = _cpu_seconds(pids)
        if now - before < 1.0:
            break
        before = now
    return time.monotonic() - started


def _gone(pid: int) -> bool:
    try:
        status = Path(f'/proc/{pid}/status').read_text()
    except (FileNotFoundError, ProcessLookupError):   # (gone between the open and the read)
        return True
    return re.search(r'^State:\s+[ZX]', status, re.M) is not None


def run_once(nodes: int, workdir: Path, *, pairs: bool = False, graph_reads: int = 0) -> dict:
    from zros.context import Context
    from zros.graph import fetch_entities

    domain = pick_domain()
    env = dict(os.environ, ZROS_DOMAIN_ID=str(domain))
    for name in ('ZROS_CONNECT', 'ZROS_DISCOVERY', 'ZROS_CONFIG'):
        env.pop(name, None)
    names = _node_names(nodes, pairs)
    path = _launch_file(workdir, names)
    out_path = workdir / 'launch.out'
    expected = {f'/{name}' for _, name in names}
    with open(out_path, 'wb') as out:
        t0 = time.monotonic()
        popen = subprocess.Popen([sys.executable, '-m', 'zros', 'launch', str(path), '--log-dir', str(workdir / 'logs')],
                                 stdout=out, stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL, env=env,
                                 cwd=REPO, start_new_session=True)
        context = None
        pids: list[int] = []
        try:
            while hub_port_free(domain):      # the supervisor becomes the hub first
                if time.monotonic() - t0 > TIMEOUT_S + 2 * nodes or popen.poll() is not None:
                    raise RuntimeError('the supervisor did not open the hub:\n' + out_path.read_text())
                time.sleep(0.005)
            os.environ['ZROS_DOMAIN_ID'] = str(domain)
            # Linked to the hub only: this script reads the graph, it must not load the nodes.
            context = Context().init([], install_signal_handlers=False, mesh=False)
            started = first = None
            while True:
                now = time.monotonic() - t0
                if started is None:   # (listeners print a lot: stop reading the output once all started)
                    text = out_path.read_text(errors='replace')
                    pids = [int(p) for p in re.findall(r'process started with pid \[(\d+)\]', text)]
                    if len(pids) >= nodes:
                        started = now
                visible = {e.node_fqn for e in fetch_entities(context.session, domain, timeout=0.5) if e.kind == 'NN'}
                seen = visible & expected
                if seen and first is None:
                    first = time.monotonic() - t0
                if seen == expected:
                    complete = time.monotonic() - t0
                    break
                if now > TIMEOUT_S + 2 * nodes:
                    missing = ', '.join(sorted(expected - seen))
                    raise RuntimeError(f'only {len(seen)} of {nodes} nodes visible after {now:.0f} s '
                                       f'(missing: {missing}); the launch output is in {workdir}')
                time.sleep(0.05)
            settle = _settle([popen.pid, *pids], 60.0 if pairs else TIMEOUT_S)   # pairs keep talking
            shares = _cpu_shares(pids, popen.pid)
            memory = [_memory_kib(pid) for pid in pids]
            supervisor = _memory_kib(popen.pid)
            reads = (_graph_reads(env, expected, graph_reads, context.session, domain, [popen.pid, *pids])
                     if graph_reads else {})
            heard = _deliveries(out_path, names) if pairs else {}
            last_cpu = {pid: _cpu_of(pid) or 0.0 for pid in pids}
            before_stop = dict(last_cpu)
            t1 = time.monotonic()
            popen.send_signal(signal.SIGINT)
            while not all(_gone(pid) for pid in pids) or popen.poll() is None:
                if time.monotonic() - t1 > 30:
                    raise RuntimeError('processes still running 30 s after SIGINT')
                for pid in pids:   # the last reading before each exits
                    last_cpu[pid] = _cpu_of(pid) or last_cpu[pid]
                time.sleep(0.005)
            shutdown = time.monotonic() - t1
            stop_cpu = sum(last_cpu[pid] - before_stop[pid] for pid in pids)
        finally:
            if context is not None:
                context.shutdown()
            for pid in [popen.pid, *pids]:
                try:
                    os.killpg(pid, signal.SIGKILL)
                except (ProcessLookupError, PermissionError):
                    pass
            popen.wait(timeout=10)
    text = out_path.read_text(errors='replace')
    return {
        'nodes': nodes, 'domain': domain, 'started_s': started, 'first_s': first, 'all_s': complete,
        'settle_s': settle, 'shutdown_s': shutdown, 'stop_cpu_s': stop_cpu, 'escalations': text.count('escalating to'),
        **shares, **reads, **heard,
        'rss_kib_mean': statistics.mean(m[0] for m in memory), 'pss_kib_mean': statistics.mean(m[1] for m in memory),
        'pss_kib_total': sum(m[1] for m in memory),
        'supervisor_rss_kib': supervisor[0], 'supervisor_pss_kib': supervisor[1],
    }


def _machine() -> str:
    """The machine line of a table, with whether Python caches byte-code (with
    PYTHONDONTWRITEBYTECODE set and no cache written before, every process compiles zros)."""
    cached = (REPO / 'zros' / '__pycache__').is_dir()
    bytecode = ('off (PYTHONDONTWRITEBYTECODE=1' + (', an old cache is read)' if cached else ', none cached)')
                if os.environ.get('PYTHONDONTWRITEBYTECODE') else 'cached')
    return (f'machine: {platform.machine()}, {os.cpu_count()} CPUs, Python {platform.python_version()}, '
            f'byte-code: {bytecode}')


def _classic_table(results: list[dict], nodes: int, runs: int) -> None:
    def med(key: str) -> float:
        return statistics.median(r[key] for r in results)

    print(f'\nzros launch benchmark: {nodes} talker nodes, {runs} runs (median; min-max)')
    print(_machine() + '\n')
    rows = [
        ('all processes started (supervisor)', 'started_s', 's'),
        ('first node in the graph', 'first_s', 's'),
        (f'all {nodes} nodes in the graph', 'all_s', 's'),
        ('Ctrl-C until everything exited', 'shutdown_s', 's'),
        ('CPU of all nodes while stopping', 'stop_cpu_s', 's'),
        ('CPU per idle node', 'node_cpu_median', '%'),
        ('CPU of the supervisor', 'supervisor_cpu', '%'),
        ('RSS per idle node', 'rss_kib_mean', 'MiB'),
        ('PSS per idle node', 'pss_kib_mean', 'MiB'),
        (f'PSS of all {nodes} nodes', 'pss_kib_total', 'MiB'),
        ('supervisor RSS', 'supervisor_rss_kib', 'MiB'),
        ('supervisor PSS', 'supervisor_pss_kib', 'MiB'),
    ]
    print(f"| {'measure':<36} | {'median':>10} | {'min - max':>17} |")
    print(f"|{'-' * 38}|{'-' * 12}|{'-' * 19}|")
    for label, key, unit in rows:
        scale = {'MiB': 1024.0, '%': 0.01}.get(unit, 1.0)
        values = [r[key] / scale for r in results]
        print(f'| {label:<36} | {med(key) / scale:>6.2f} {unit:<3} | {min(values):>7.2f} - {max(values):>7.2f} |')


def _load_table(results: list[dict], reads: int, pairs: bool) -> None:
    """One column per launch size, the goal beside each row, MISS where it is not met."""
    kind = 'talker/listener pairs (every listener hears every talker)' if pairs else 'talkers only'
    print(f'\nzros launch under load: {kind}, {reads} reads of each list verb')
    print(f'{_machine()}, load average at the end: {os.getloadavg()[0]:.1f}\n')

    def times(key: str):
        return lambda r: f'{statistics.median(r[key]):.2f} s ({max(r[key]):.2f})', \
            lambda r: max(r[key]) < 1.0
    rows = [
        ('`zros node list`, median (max)', *times('node_list_s'), '< 1 s every time'),
        ('`zros topic list`, median (max)', *times('topic_list_s'), '< 1 s every time'),
        ('graph read alone (open session), median (max)', *times('read_in_process_s'), '< 1 s every time'),
        ('node list answers complete', lambda r: f"{r['complete_reads']}/{reads}",
         lambda r: r['complete_reads'] == reads, 'all'),
        *([('listeners hearing every talker (slowest, msg/s)',
            lambda r: f"{r['hearing_all']}/{r['listeners']} ({r['heard_min_per_s']:.1f} of {r['talkers']})",
            lambda r: r['hearing_all'] == r['listeners'], 'all')] if pairs else []),
        ('CPU per list command, median (max)', *times('cli_cpu_s')[:1], None, ''),
        ('load average during the reads', lambda r: f"{r['load_during_reads']:.0f}", None, ''),
        ('CPUs busy during the reads (of which the launch)',
         lambda r: f"{100 * r['machine_busy']:.0f} % ({r['launch_cpus']:.2f} CPUs)", None, ''),
        ('all nodes in the graph after start', lambda r: f"{r['all_s']:.1f} s", None, ''),
        ('then settled (< 0.5 CPU) after', lambda r: f"{r['settle_s']:.1f} s", None, ''),
        ('Ctrl-C until everything exited', lambda r: f"{r['shutdown_s']:.2f} s", lambda r: r['shutdown_s'] < 3.0,
         '< 3 s'),
        ('CPU of all nodes while stopping', lambda r: f"{r['stop_cpu_s']:.1f} s", None, ''),
        ('escalations to SIGTERM/SIGKILL', lambda r: str(r['escalations']), lambda r: r['escalations'] == 0, '0'),
        ('CPU per node once settled, median (max)',
         lambda r: f"{100 * r['node_cpu_median']:.1f} % ({100 * r['node_cpu_max']:.1f})", None, ''),
        ('CPU of all nodes once settled', lambda r: f"{r['nodes_cpu_total']:.2f} CPUs", None, ''),
        ('CPU of the supervisor once settled', lambda r: f"{100 * r['supervisor_cpu']:.1f} %", None, ''),
        ('PSS per idle node', lambda r: f"{r['pss_kib_mean'] / 1024:.1f} MiB", None, ''),
        ('RSS per idle node', lambda r: f"{r['rss_kib_mean'] / 1024:.1f} MiB", None, ''),
        ('PSS of all nodes', lambda r: f"{r['pss_kib_total'] / 1024:.0f} MiB", None, ''),
        ('supervisor PSS', lambda r: f"{r['supervisor_pss_kib'] / 1024:.1f} MiB", None, ''),
    ]
    header = ['measure'] + [f"{r['nodes']} nodes" for r in results] + ['goal']
    print('| ' + ' | '.join(header) + ' |')
    print('|' + '|'.join('---' for _ in header) + '|')
    for label, show, ok, goal in rows:
        cells = [show(r) + ('' if ok is None or ok(r) else ' MISS') for r in results]
        print('| ' + ' | '.join([label, *cells, goal]) + ' |')


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--nodes', type=int, nargs='+', default=None, help='launch sizes (default 20)')
    parser.add_argument('--runs', type=int, default=None, help='runs per size (default 3; 1 with --load)')
    parser.add_argument('--pairs', action='store_true', help='talker/listener pairs instead of talkers')
    parser.add_argument('--graph-reads', type=int, default=None, metavar='R',
                        help='time R `zros node list` and `zros topic list` runs per launch (default 0; 5 with --load)')
    parser.add_argument('--load', action='store_true', help='50 and 100 nodes, pairs, graph reads, one run each')
    parser.add_argument('--json', metavar='FILE', help='also write the results as JSON')
    args = parser.parse_args()
    if not sys.platform.startswith('linux'):
        print('this benchmark reads /proc and runs on Linux only', file=sys.stderr)
        return 1
    sizes = args.nodes or ([50, 100] if args.load else [20])
    runs = args.runs or (1 if args.load else 3)
    reads = args.graph_reads if args.graph_reads is not None else (5 if args.load else 0)
    pairs = args.pairs or args.load
    results = []
    for nodes in sizes:
        for run in range(runs):
            workdir = Path(tempfile.mkdtemp(prefix='zros-bench-launch-'))
            result = run_once(nodes, workdir, pairs=pairs, graph_reads=reads)
            shutil.rmtree(workdir)   # kept, and named in the error, when a run fails
            results.append(result)
            if args.json:   # after every run: a long series that fails later keeps what it measured
                Path(args.json).write_text(json.dumps(results, indent=2))
            print(f"{nodes} nodes, run {run + 1}: all in the graph after {result['all_s']:.2f} s, "
                  f"stopped in {result['shutdown_s']:.2f} s", file=sys.stderr)
    if reads:
        _load_table(results, reads, pairs)
    else:
        for nodes in sizes:
            _classic_table([r for r in results if r['nodes'] == nodes], nodes, runs)
    return 0


if __name__ == '__main__':
    sys.exit(main())
