"""Service and action round trips: zros against a raw Zenoh get, same run, same machine.

    python benchmarks/services.py            # about 20 s
    python benchmarks/services.py --quick    # a few seconds

A server process answers (1) a raw zenoh-python queryable that decodes a msgpack request
{a, b} and replies {sum}, and (2) zros's `example_interfaces/srv/AddTwoInts` service and a
trivial `action_tutorials_interfaces/action/Fibonacci` action server (its execute callback
succeeds at once). This process is the client: raw `session.get` calls, then
`Client.call`, then `ActionClient.send_goal` (send-goal plus get-result), in alternating
rounds. Targets from docs/architecture.md §8: a service call within 1.5x of a raw get, an action goal round
trip within 3x.
"""
from __future__ import annotations

import argparse
import os
import subprocess
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(REPO), str(Path(__file__).resolve().parent)]

from pubsub import machine_facts, percentile, pick_domain, table, worker_env  # noqa: E402

SERVICE_TARGET, ACTION_TARGET = 1.5, 3.0
RAW_KEY = 'zros_bench/raw_add'


def serve() -> None:
    """The server process: raw queryable, zros service and zros action server."""
    import msgpack

    import zros
    from zros.action import ActionServer
    from zros.executors import SingleThreadedExecutor
    from zros.node import Node

    from interfaces.action_tutorials_interfaces.action import Fibonacci
    from interfaces.example_interfaces.srv import AddTwoInts

    context = zros.init([])
    session = context.session

    def on_raw(query) -> None:
        request = msgpack.unpackb(query.payload.to_bytes())
        query.reply(query.key_expr, msgpack.packb({'sum': request['a'] + request['b']}))

    queryable = session.declare_queryable(RAW_KEY, on_raw, complete=True)
    node = Node('bench_server')

    def add(request, response):
        response.sum = request.a + request.b
        return response

    def execute(goal_handle):
        goal_handle.succeed()
        return Fibonacci.Result(sequence=[goal_handle.request.order])
    node.create_service(AddTwoInts, 'bench_add', add)
    ActionServer(node, Fibonacci, 'bench_fib', execute)
    executor = SingleThreadedExecutor()
    executor.add_node(node)
    print('ready', flush=True)
    import threading
    threading.Thread(target=lambda: (sys.stdin.read(), zros.shutdown()), daemon=True).start()
    try:
        executor.spin()
    except Exception:  # noqa: BLE001 - ends with the context
        pass
    queryable.undeclare()


def measure_raw(session, count: int) -> list[int]:
    import msgpack
    rtts = []
    for i in range(count):
        start = time.perf_counter_ns()
        replies = list(session.get(RAW_KEY, payload=msgpack.packb({'a': i, 'b': 1}), timeout=5.0))
        answer = msgpack.unpackb(replies[0].ok.payload.to_bytes())
        rtts.append(time.perf_counter_ns() - start)
        assert answer['sum'] == i + 1
    return rtts


def measure_service(client, srv, count: int) -> list[int]:
    rtts = []
    for i in range(count):
        start = time.perf_counter_ns()
        response = client.call(srv.Request(a=i, b=1), timeout_sec=5.0)
        rtts.append(time.perf_counter_ns() - start)
        assert response.sum == i + 1
    return rtts


def measure_action(client, action, count: int) -> list[int]:
    rtts = []
    for i in range(count):
        start = time.perf_counter_ns()
        result = client.send_goal(action.Goal(order=i))
        rtts.append(time.perf_counter_ns() - start)
        assert list(result.result.sequence) == [i]
    return rtts


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--quick', action='store_true', help='fewer calls, one round')
    parser.add_argument('--serve', action='store_true', help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.serve:
        serve()
        return 0
    calls, action_calls, rounds = (300, 100, 1) if args.quick else (1500, 300, 3)
    domain = pick_domain()
    env = worker_env(domain)
    os.environ.update({'ZROS_DOMAIN_ID': str(domain)})
    server = subprocess.Popen([sys.executable, __file__, '--serve'], stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                              env=env, text=True)
    try:
        if server.stdout.readline().strip() != 'ready':
            raise SystemExit('the server did not start')
        import zros
        from zros.action import ActionClient
        from zros.node import Node

        from interfaces.action_tutorials_interfaces.action import Fibonacci
        from interfaces.example_interfaces.srv import AddTwoInts
        context = zros.init([])
        node = Node('bench_client')
        service = node.create_client(AddTwoInts, 'bench_add')
        action = ActionClient(node, Fibonacci, 'bench_fib')
        if not (service.wait_for_service(10) and action.wait_for_server(10)):
            raise SystemExit('the server never appeared in the graph')
        samples: dict[str, list[int]] = {'raw': [], 'service': [], 'action': []}
        measure_raw(context.session, 50)  # warm-up
        measure_service(service, AddTwoInts, 50)
        measure_action(action, Fibonacci, 20)
        for round_index in range(rounds):
            order = ('raw', 'service', 'action') if round_index % 2 == 0 else ('action', 'service', 'raw')
            for kind in order:
                if kind == 'raw':
                    samples[kind] += measure_raw(context.session, calls)
                elif kind == 'service':
                    samples[kind] += measure_service(service, AddTwoInts, calls)
                else:
                    samples[kind] += measure_action(action, Fibonacci, action_calls)
        zros.shutdown()
    finally:
        server.stdin.close()
        try:
            server.wait(timeout=10)
        except subprocess.TimeoutExpired:
            server.kill()
    stats = {k: (percentile(sorted(v), 50) / 1000, percentile(sorted(v), 90) / 1000) for k, v in samples.items()}
    raw_median = stats['raw'][0]
    rows = [['raw zenoh get', f'{stats["raw"][0]:.0f}', f'{stats["raw"][1]:.0f}', '1.00x', '', '']]
    for kind, label, target in (('service', 'zros service call', SERVICE_TARGET),
                                ('action', 'zros action goal -> result', ACTION_TARGET)):
        ratio = stats[kind][0] / raw_median
        rows.append([label, f'{stats[kind][0]:.0f}', f'{stats[kind][1]:.0f}', f'{ratio:.2f}x',
                     f'<= {target:.1f}x', 'PASS' if ratio <= target else 'MISS'])
    facts = machine_facts()
    print(f"machine: {facts['nproc']} cores, {facts['cpu']}, Python {facts['python']}, "
          f"eclipse-zenoh {facts['eclipse-zenoh']}")
    print(f'round trips in microseconds ({len(samples["raw"])} raw, {len(samples["service"])} service, '
          f'{len(samples["action"])} action calls)')
    print(table(['case', 'median', 'p90', 'vs raw get', 'target', 'result'], rows))
    return 0


if __name__ == '__main__':
    sys.exit(main())
