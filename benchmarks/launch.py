"""Launch benchmark: how long `zros launch` takes to bring N nodes into the graph, what an idle
node costs in memory, and how long Ctrl-C takes to bring everything down.

    python benchmarks/launch.py                 # 20 talkers, 3 runs
    python benchmarks/launch.py --nodes 10 --runs 1
    python benchmarks/launch.py --json out.json

Each run writes a launch file with N `demo_nodes/talker` nodes (distinct names `talker_00` ..),
starts `python -m zros launch FILE` in a fresh domain (from 201 up, first with a free hub port)
and measures, from just before the supervisor process is spawned:
- `started`: when the supervisor has reported `process started` for all N (its own overhead);
- `first` / `all`: when the first / all N node names are visible in the graph, read by this
  script with `zros.graph.fetch_entities` every 50 ms (this script connects only once the
  supervisor holds the hub port, so the launch is the hub, as on a fresh machine);
- memory of each node after the graph is complete and everything has idled for 2 s:
  RSS and PSS from /proc/<pid>/smaps_rollup (PSS splits shared pages, such as the Python
  binary and the zenoh library, between the processes that map them), and the supervisor's;
- `shutdown`: from SIGINT to the supervisor until it and every node have exited.
"""
from __future__ import annotations

import argparse
import json
import os
import platform
import re
import signal
import socket
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
if str(REPO) not in sys.path:
    sys.path.insert(0, str(REPO))

HUB_BASE_PORT = 7447
DOMAIN_BASE = 201
TIMEOUT_S = 120.0


def _port_free(port: int) -> bool:
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as probe:
        probe.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        try:
            probe.bind(('127.0.0.1', port))
        except OSError:
            return False
    return True


def _free_domain() -> int:
    for domain in range(DOMAIN_BASE, 233):
        if _port_free(HUB_BASE_PORT + domain):
            return domain
    raise RuntimeError('no free zros domain')


def _launch_file(directory: Path, nodes: int) -> Path:
    lines = ['launch:']
    for index in range(nodes):
        lines.append(f'- node: {{pkg: demo_nodes, exec: talker, name: talker_{index:02d}}}')
    path = directory / 'bench.launch.yaml'
    path.write_text('\n'.join(lines) + '\n')
    return path


def _memory_kib(pid: int) -> tuple[int, int]:
    """(RSS, PSS) in KiB of one process."""
    text = Path(f'/proc/{pid}/smaps_rollup').read_text()
    rss = int(re.search(r'^Rss:\s+(\d+) kB', text, re.M).group(1))
    pss = int(re.search(r'^Pss:\s+(\d+) kB', text, re.M).group(1))
    return rss, pss


def _gone(pid: int) -> bool:
    try:
        status = Path(f'/proc/{pid}/status').read_text()
    except FileNotFoundError:
        return True
    return re.search(r'^State:\s+[ZX]', status, re.M) is not None


def run_once(nodes: int, workdir: Path) -> dict:
    from zros.context import Context
    from zros.graph import fetch_entities

    domain = _free_domain()
    env = dict(os.environ, ZROS_DOMAIN_ID=str(domain))
    for name in ('ZROS_CONNECT', 'ZROS_DISCOVERY', 'ZROS_CONFIG'):
        env.pop(name, None)
    path = _launch_file(workdir, nodes)
    out_path = workdir / 'launch.out'
    expected = {f'/talker_{i:02d}' for i in range(nodes)}
    with open(out_path, 'wb') as out:
        t0 = time.monotonic()
        popen = subprocess.Popen([sys.executable, '-m', 'zros', 'launch', str(path), '--log-dir', str(workdir / 'logs')],
                                 stdout=out, stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL, env=env,
                                 cwd=REPO, start_new_session=True)
        context = None
        pids: list[int] = []
        try:
            while _port_free(HUB_BASE_PORT + domain):      # the supervisor becomes the hub first
                if time.monotonic() - t0 > TIMEOUT_S or popen.poll() is not None:
                    raise RuntimeError('the supervisor did not open the hub:\n' + out_path.read_text())
                time.sleep(0.005)
            os.environ['ZROS_DOMAIN_ID'] = str(domain)
            context = Context().init([], install_signal_handlers=False)
            started = first = None
            while True:
                now = time.monotonic() - t0
                text = out_path.read_text(errors='replace')
                pids = [int(p) for p in re.findall(r'process started with pid \[(\d+)\]', text)]
                if started is None and len(pids) >= nodes:
                    started = now
                names = {e.node_fqn for e in fetch_entities(context.session, domain, timeout=0.5) if e.kind == 'NN'}
                seen = names & expected
                if seen and first is None:
                    first = time.monotonic() - t0
                if seen == expected:
                    complete = time.monotonic() - t0
                    break
                if now > TIMEOUT_S:
                    raise RuntimeError(f'only {len(seen)} of {nodes} nodes visible after {TIMEOUT_S} s')
                time.sleep(0.05)
            time.sleep(2.0)
            memory = [_memory_kib(pid) for pid in pids]
            supervisor = _memory_kib(popen.pid)
            t1 = time.monotonic()
            popen.send_signal(signal.SIGINT)
            popen.wait(timeout=30)
            while not all(_gone(pid) for pid in pids):
                if time.monotonic() - t1 > 30:
                    raise RuntimeError('nodes still running 30 s after SIGINT')
                time.sleep(0.005)
            shutdown = time.monotonic() - t1
        finally:
            if context is not None:
                context.shutdown()
            for pid in [popen.pid, *pids]:
                try:
                    os.killpg(pid, signal.SIGKILL)
                except (ProcessLookupError, PermissionError):
                    pass
            popen.wait(timeout=10)
    return {
        'nodes': nodes, 'domain': domain, 'started_s': started, 'first_s': first, 'all_s': complete,
        'shutdown_s': shutdown,
        'rss_kib_mean': statistics.mean(m[0] for m in memory), 'pss_kib_mean': statistics.mean(m[1] for m in memory),
        'pss_kib_total': sum(m[1] for m in memory),
        'supervisor_rss_kib': supervisor[0], 'supervisor_pss_kib': supervisor[1],
    }


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--nodes', type=int, default=20)
    parser.add_argument('--runs', type=int, default=3)
    parser.add_argument('--json', metavar='FILE', help='also write the results as JSON')
    args = parser.parse_args()
    if not sys.platform.startswith('linux'):
        print('this benchmark reads /proc and runs on Linux only', file=sys.stderr)
        return 1
    results = []
    for run in range(args.runs):
        with tempfile.TemporaryDirectory(prefix='zros-bench-launch-') as tmp:
            result = run_once(args.nodes, Path(tmp))
        results.append(result)
        print(f"run {run + 1}: all {args.nodes} nodes in the graph after {result['all_s']:.2f} s", file=sys.stderr)

    def med(key: str) -> float:
        return statistics.median(r[key] for r in results)

    print(f'\nzros launch benchmark: {args.nodes} talker nodes, {args.runs} runs (median; min-max)')
    print(f'machine: {platform.machine()}, {os.cpu_count()} CPUs, Python {platform.python_version()}\n')
    rows = [
        ('all processes started (supervisor)', 'started_s', 's'),
        ('first node in the graph', 'first_s', 's'),
        (f'all {args.nodes} nodes in the graph', 'all_s', 's'),
        ('Ctrl-C until everything exited', 'shutdown_s', 's'),
        ('RSS per idle node', 'rss_kib_mean', 'MiB'),
        ('PSS per idle node', 'pss_kib_mean', 'MiB'),
        (f'PSS of all {args.nodes} nodes', 'pss_kib_total', 'MiB'),
        ('supervisor RSS', 'supervisor_rss_kib', 'MiB'),
        ('supervisor PSS', 'supervisor_pss_kib', 'MiB'),
    ]
    print(f"| {'measure':<36} | {'median':>10} | {'min - max':>17} |")
    print(f"|{'-' * 38}|{'-' * 12}|{'-' * 19}|")
    for label, key, unit in rows:
        scale = 1024.0 if unit == 'MiB' else 1.0
        values = [r[key] / scale for r in results]
        print(f'| {label:<36} | {med(key) / scale:>6.2f} {unit:<3} | {min(values):>7.2f} - {max(values):>7.2f} |')
    if args.json:
        Path(args.json).write_text(json.dumps(results, indent=2))
    return 0


if __name__ == '__main__':
    sys.exit(main())
