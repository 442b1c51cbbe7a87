"""The scene view under a navigation-sized load: server CPU, bytes to the browser, page frame rate,
and the latency from a message published to its scene update.

    python benchmarks/view.py            # about 100 s
    python benchmarks/view.py --quick    # about 50 s: shorter windows

The load is `zros run zros_view fake_robot` with the robot driving: a 384 x 384 map re-published
(unchanged) at 1 Hz, a 360-beam scan at 5 Hz, TF at 30 Hz, 2000 particles at 5 Hz, AMCL's pose,
a 60-pose plan and frontier markers at 1 Hz. Two phases:

1. **Server and page.** `zros view` runs in its own process with every display on (auto mode);
   headless Chromium (software WebGL) opens the page. Over the window we read the server
   process's CPU time (/proc), the bytes its websocket sent (the kernel's TCP counters, read
   with `ss`) and the page's frame rate (requestAnimationFrame callbacks per second).
2. **Latency.** A SceneView in this process, with the same load and a browser connected; this
   process also publishes a LaserScan in the fixed frame at 10 Hz and times each one from
   `publish()` to the end of its display's scene update (the arrays handed to viser, which
   sends them on its next flush).

3. **rqt_plot.** `zros rqt /bench_twist/linear/x:y` in its own process, its Plot page open in
   the browser, while `zros topic pub -r 50` publishes the topic: the rqt process's CPU and the
   bytes it sends (the page gets at most 500 points per series twice a second, whatever the rate).

Goals (docs/architecture.md §9, issue 19): server < 10 % of a core, page >= 30 fps, latency < 50 ms; the same
CPU goal for the plot page (issue 24: plotting at 50 Hz must not load the graph).
"""
from __future__ import annotations

import argparse
import os
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(REPO), str(Path(__file__).resolve().parent)]

from pubsub import machine_facts, percentile, pick_domain, table, worker_env  # noqa: E402

CPU_GOAL, FPS_GOAL, LATENCY_GOAL = 10.0, 30.0, 50.0
PLOT_RATE = 50.0           # [Hz] the topic rqt_plot's page plots (issue 24: "plotting at 50 Hz")
LOAD_ARGS = ['--ros-args', '-p', 'map_rate:=1.0', '-p', 'particles:=2000', '-p', 'speed:=0.15']


def _cpu_seconds(pid: int) -> float:
    with open(f'/proc/{pid}/stat') as handle:
        fields = handle.read().rsplit(')', 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf('SC_CLK_TCK')


def _bytes_sent(port: int) -> int:
    """Bytes the server's TCP sockets on `port` have sent (the kernel's count, via iproute2's ss)."""
    import re
    out = subprocess.run(['ss', '-tinH', 'state', 'established', f'( sport = :{port} )'], capture_output=True,
                         text=True, check=True).stdout
    return sum(int(n) for n in re.findall(r'bytes_sent:(\d+)', out))


def _spawn(argv: list[str], env: dict[str, str]) -> subprocess.Popen:
    return subprocess.Popen(argv, cwd=REPO, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                            stdin=subprocess.DEVNULL, start_new_session=True)


def _stop(process: subprocess.Popen) -> None:
    try:
        os.killpg(process.pid, signal.SIGTERM)
        process.wait(timeout=5)
    except (ProcessLookupError, subprocess.TimeoutExpired):
        try:
            os.killpg(process.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass


def _wait_line(process: subprocess.Popen, text: str, timeout: float) -> str:
    deadline = time.monotonic() + timeout
    assert process.stdout is not None
    os.set_blocking(process.stdout.fileno(), False)
    seen = ''
    while time.monotonic() < deadline:
        seen += (process.stdout.read() or b'').decode(errors='replace')
        for line in seen.splitlines():
            if text in line:
                return line
        if process.poll() is not None:
            break
        time.sleep(0.1)
    raise RuntimeError(f'no "{text}" from {process.args}: {seen[-400:]}')


def phase_server(window: float) -> dict:
    """Server CPU, websocket bytes/s and page fps with `zros view` in its own process."""
    from zros.view.headless import Browser
    domain = pick_domain()
    env = worker_env(domain)
    robot = _spawn([sys.executable, '-m', 'zros.cli.main', 'run', 'zros_view', 'fake_robot', *LOAD_ARGS], env)
    view = _spawn([sys.executable, '-m', 'zros.cli.main', 'view', '--port', '0'], env)
    try:
        url = _wait_line(view, 'serving', 30).split('serving ', 1)[1].split()[0]
        with Browser(width=1400, height=850) as browser:
            browser.open(url, wait_for='document.querySelector("canvas")', timeout=60)
            time.sleep(8)                                   # displays appear, first map sent
            port = int(url.rstrip('/').rsplit(':', 1)[1])
            cpu0, sent0, t0 = _cpu_seconds(view.pid), _bytes_sent(port), time.monotonic()
            time.sleep(window)
            cpu1, sent1, t1 = _cpu_seconds(view.pid), _bytes_sent(port), time.monotonic()
            fps = browser.frame_rate(min(5.0, window / 2))
        return {'cpu_percent': 100.0 * (cpu1 - cpu0) / (t1 - t0), 'bytes_per_s': (sent1 - sent0) / (t1 - t0),
                'fps': fps, 'window_s': t1 - t0}
    finally:
        _stop(view)
        _stop(robot)


def _spin(executor) -> None:
    from zros.executors import ExternalShutdownException
    try:
        executor.spin()
    except ExternalShutdownException:                       # the phase's context shut down
        pass


def phase_latency(samples: int) -> dict:
    """Publish-to-scene-update latency of a LaserScan display, under the same load."""
    import numpy as np

    from interfaces.sensor_msgs.msg import LaserScan
    from zros.context import Context
    from zros.executors import MultiThreadedExecutor
    from zros.node import Node
    from zros.view.headless import Browser
    from zros.view.scene.app import SceneView
    from zros.view.scene.displays.base import stamp_ns
    domain = pick_domain()
    env = worker_env(domain)
    os.environ['ZROS_DOMAIN_ID'] = str(domain)
    robot = _spawn([sys.executable, '-m', 'zros.cli.main', 'run', 'zros_view', 'fake_robot', *LOAD_ARGS], env)
    ctx = Context().init([], install_signal_handlers=False)
    try:
        node = Node('view_bench', context=ctx)
        executor = MultiThreadedExecutor(context=ctx)
        executor.add_node(node)
        threading.Thread(target=_spin, args=(executor,), daemon=True).start()
        view = SceneView(node, port=0)
        sent: dict[int, float] = {}
        latencies: list[float] = []
        try:
            with Browser(width=1400, height=850) as browser:
                browser.open(view.url, wait_for='document.querySelector("canvas")', timeout=60)
                from zros.view.scene.config import DisplayConfig
                display = view.add_display(DisplayConfig('LaserScan', 'bench', '/bench_scan'))
                original = display.draw

                def timed(msg, pose):
                    original(msg, pose)
                    start = sent.pop(stamp_ns(msg.header), None)
                    if start is not None:
                        latencies.append((time.monotonic() - start) * 1000.0)
                display.draw = timed
                publisher = node.create_publisher(LaserScan, '/bench_scan', 10)
                time.sleep(6)                               # the load's displays are up
                ranges = np.full(360, 2.0, dtype=np.float32)
                for i in range(samples + 10):
                    scan = LaserScan(angle_increment=2 * np.pi / 360, range_min=0.1, range_max=5.0, ranges=ranges)
                    scan.header.frame_id = view.ctx.fixed_frame
                    scan.header.stamp.sec, scan.header.stamp.nanosec = 1000 + i, 0
                    sent[stamp_ns(scan.header)] = time.monotonic()
                    publisher.publish(scan)
                    time.sleep(0.1)
                time.sleep(1.0)
        finally:
            view.close()
        values = sorted(latencies[10:])
        return {'median_ms': percentile(values, 50), 'p95_ms': percentile(values, 95), 'samples': len(values),
                'lost': samples + 10 - len(latencies)}
    finally:
        ctx.shutdown()
        _stop(robot)


def phase_plot(window: float, rate: float = PLOT_RATE) -> dict:
    """rqt_plot's page on a `rate` Hz topic: the rqt process's CPU and the bytes it sends."""
    from zros.view.headless import Browser
    domain = pick_domain()
    env = worker_env(domain)
    publisher = _spawn([sys.executable, '-m', 'zros.cli.main', 'topic', 'pub', '-r', f'{rate:g}', '/bench_twist',
                        'geometry_msgs/msg/Twist', '{linear: {x: 1.0, y: 2.0}}'], env)
    rqt = _spawn([sys.executable, '-m', 'zros.cli.main', 'rqt', '/bench_twist/linear/x:y', '--port', '0'], env)
    try:
        url = _wait_line(rqt, 'serving', 30).split('serving ', 1)[1].split()[0]
        with Browser(width=1400, height=850) as browser:
            browser.open(url, wait_for='document.querySelector(".uplot")', timeout=60)
            browser.wait_for('document.body.innerText.includes("/bench_twist/linear/y: 2")', timeout=30)
            time.sleep(3)
            port = int(url.rstrip('/').rsplit(':', 1)[1])
            cpu0, sent0, t0 = _cpu_seconds(rqt.pid), _bytes_sent(port), time.monotonic()
            time.sleep(window)
            cpu1, sent1, t1 = _cpu_seconds(rqt.pid), _bytes_sent(port), time.monotonic()
        return {'cpu_percent': 100.0 * (cpu1 - cpu0) / (t1 - t0), 'bytes_per_s': (sent1 - sent0) / (t1 - t0)}
    finally:
        _stop(rqt)
        _stop(publisher)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--quick', action='store_true', help='shorter windows (about 50 s)')
    args = parser.parse_args()
    window, samples = (8.0, 40) if args.quick else (20.0, 150)
    facts = machine_facts()
    print(f"# view benchmark: {facts['nproc']} cores, {facts['cpu']}, Python {facts['python']}")
    server = phase_server(window)
    latency = phase_latency(samples)
    plot = phase_plot(window)
    rows = [
        ['server CPU (one core = 100 %)', f"{server['cpu_percent']:.1f} %", f'< {CPU_GOAL:g} %',
         'ok' if server['cpu_percent'] < CPU_GOAL else 'MISS'],
        ['bytes/s sent to the browser (websocket)', f"{server['bytes_per_s'] / 1000:.0f} kB/s", '-', ''],
        ['page frame rate (headless, software WebGL)', f"{server['fps']:.1f} fps", f'>= {FPS_GOAL:g} fps',
         'ok' if server['fps'] >= FPS_GOAL else 'MISS'],
        ['publish -> scene update, median', f"{latency['median_ms']:.1f} ms", f'< {LATENCY_GOAL:g} ms',
         'ok' if latency['median_ms'] < LATENCY_GOAL else 'MISS'],
        ['publish -> scene update, p95', f"{latency['p95_ms']:.1f} ms", '', ''],
        [f'rqt plot of 2 fields at {PLOT_RATE:g} Hz: server CPU', f"{plot['cpu_percent']:.1f} %",
         f'< {CPU_GOAL:g} %', 'ok' if plot['cpu_percent'] < CPU_GOAL else 'MISS'],
        [f'rqt plot at {PLOT_RATE:g} Hz: bytes/s sent to the browser', f"{plot['bytes_per_s'] / 1000:.1f} kB/s",
         '-', ''],
    ]
    print(table(['measure', 'value', 'goal', ''], rows))
    print(f"(window {server['window_s']:.0f} s; latency over {latency['samples']} scans, {latency['lost']} not drawn)")
    return 0


if __name__ == '__main__':
    sys.exit(main())
