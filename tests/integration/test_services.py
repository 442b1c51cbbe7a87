"""Services end to end: real server processes and clients over loopback Zenoh."""
from __future__ import annotations

import threading
import time

import pytest

from conftest import wait_until
from zros.errors import ServiceCallError
from zros.executors import MultiThreadedExecutor, SingleThreadedExecutor
from zros.node import Node


@pytest.fixture
def add_two_ints():
    from interfaces.example_interfaces.srv import AddTwoInts
    return AddTwoInts


@pytest.fixture
def server_process(spawn):
    child = spawn.node('demo_nodes', 'add_two_ints_server')
    return child


def _client(context, srv_type, name='add_two_ints'):
    node = Node('test_client', context=context)
    client = node.create_client(srv_type, name)
    assert client.wait_for_service(timeout_sec=10.0), 'server never appeared in the graph'
    return node, client


def test_sync_and_async_calls_to_a_server_process(context, server_process, add_two_ints):
    node, client = _client(context, add_two_ints)
    assert client.service_is_ready()
    assert client.call(add_two_ints.Request(a=2, b=3), timeout_sec=5).sum == 5
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(node)
    future = client.call_async(add_two_ints.Request(a=40, b=2))
    done = []
    future.add_done_callback(lambda f: done.append(threading.current_thread()))
    executor.spin_until_future_complete(future, timeout_sec=5)
    assert future.done() and future.exception() is None
    assert future.result().sum == 42
    deadline = time.monotonic() + 10.0
    while not done and time.monotonic() < deadline:
        executor.spin_once(timeout_sec=0.5)  # done callbacks run on the executor
    assert done == [threading.current_thread()]
    assert 'Incoming request' in server_process.wait_for_output('a: 40 b: 2')


def test_call_async_reply_is_decoded_by_the_thread_that_reads_it(context, server_process, add_two_ints):
    """Zenoh's thread only completes the future; the executor that runs the done callback
    decodes the reply (and a reply is decoded once, however many threads read it)."""
    node, client = _client(context, add_two_ints)
    decoded_on = []
    outcome = client._outcome
    client._outcome = lambda *args: decoded_on.append(threading.current_thread()) or outcome(*args)
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(node)
    future = client.call_async(add_two_ints.Request(a=1, b=2))
    sums = []
    future.add_done_callback(lambda f: sums.append(f.result().sum))
    assert future.wait(10.0), 'no reply'
    assert decoded_on == []   # completed, not yet decoded
    deadline = time.monotonic() + 10.0
    while not sums and time.monotonic() < deadline:
        executor.spin_once(timeout_sec=0.5)   # one turn may serve the completion notice first
    assert sums == [3] and future.result().sum == 3
    assert decoded_on == [threading.current_thread()]


def test_client_demo_prints_the_result(spawn, server_process):
    client = spawn.node('demo_nodes', 'add_two_ints_client', '3', '4')
    assert client.wait(timeout=15) == 0
    assert 'Result of add_two_ints: for 3 + 4 = 7' in client.output()


def test_many_concurrent_clients_get_their_own_answers(context, server_process, add_two_ints):
    node, client = _client(context, add_two_ints)
    errors, answers = [], []

    def worker(k: int) -> None:
        try:
            for i in range(50):
                response = client.call(add_two_ints.Request(a=k * 1000, b=i), timeout_sec=10)
                answers.append((k, i, response.sum))
        except Exception as exc:  # noqa: BLE001 - collected and asserted below
            errors.append(exc)
    threads = [threading.Thread(target=worker, args=(k,)) for k in range(8)]
    for t in threads:
        t.start()
    for t in threads:
        t.join(timeout=60)
    assert not errors
    assert len(answers) == 400
    assert all(total == k * 1000 + i for k, i, total in answers)


def test_server_exception_reaches_the_client_and_server_keeps_serving(make_context, add_two_ints):
    server_ctx, client_ctx = make_context(), make_context()
    server = Node('flaky_server', context=server_ctx)

    def handler(request, response):
        if request.a < 0:
            raise ValueError('negative numbers are not allowed')
        response.sum = request.a + request.b
        return response
    server.create_service(add_two_ints, 'flaky', handler)
    executor = MultiThreadedExecutor(context=server_ctx)
    executor.add_node(server)
    spinner = threading.Thread(target=lambda: _spin_quietly(executor), daemon=True)
    spinner.start()
    _, client = _client(client_ctx, add_two_ints, 'flaky')
    with pytest.raises(ServiceCallError, match='ValueError: negative numbers are not allowed'):
        client.call(add_two_ints.Request(a=-1, b=1), timeout_sec=5)
    assert client.call(add_two_ints.Request(a=1, b=1), timeout_sec=5).sum == 2
    executor.shutdown()


def test_a_response_of_the_wrong_type_fails_the_call_and_raises_in_spin(context, add_two_ints):
    """rclpy raises the server's TypeError out of spin; zros also tells the client why."""
    node = Node('sloppy_server', context=context)
    node.create_service(add_two_ints, 'sloppy', lambda request, response: 'not a response')
    client = node.create_client(add_two_ints, 'sloppy')
    assert client.wait_for_service(timeout_sec=10.0)
    future = client.call_async(add_two_ints.Request(a=1, b=2))
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(node)
    with pytest.raises(TypeError, match='callback returned str'):
        executor.spin_until_future_complete(future, timeout_sec=5)
    assert wait_until(future.done, timeout=5)
    assert isinstance(future.exception(), ServiceCallError)
    executor.shutdown()


def _spin_quietly(executor) -> None:
    try:
        executor.spin()
    except Exception:  # noqa: BLE001 - ends with the context
        pass


def test_missing_server_times_out(context, add_two_ints):
    node = Node('lonely', context=context)
    client = node.create_client(add_two_ints, 'nobody_home')
    assert not client.wait_for_service(timeout_sec=0.3)
    started = time.monotonic()
    assert client.call(add_two_ints.Request(a=1, b=2), timeout_sec=0.5) is None   # rclpy's timeout answer
    assert time.monotonic() - started < 3


def test_a_call_made_before_its_server_starts_is_answered_once_it_does(context, spawn, add_two_ints):
    """Seed 003's integration test calls at once, beside a server still starting: the request
    waits for a server to be reachable, then goes (rclpy would hang; failing would lose it)."""
    node = Node('early_client', context=context)
    client = node.create_client(add_two_ints, 'add_two_ints')
    future = client.call_async(add_two_ints.Request(a=2, b=3))
    blocking = []
    caller = threading.Thread(target=lambda: blocking.append(client.call(add_two_ints.Request(a=4, b=5))))
    caller.start()
    assert not future.done()
    spawn.node('demo_nodes', 'add_two_ints_server')
    assert future.wait(15), 'the early request was never sent'
    assert future.result().sum == 5
    caller.join(15)
    assert [response.sum for response in blocking] == [9]


def test_a_call_after_its_server_went_away_fails_at_once(context, spawn, add_two_ints):
    """Only a client that never reached a server waits for one: a lifecycle manager calling a
    crashed node must learn it now (SERVER_WAIT_SEC is 10 s)."""
    server = spawn.node('demo_nodes', 'add_two_ints_server')
    node, client = _client(context, add_two_ints)
    assert client.call(add_two_ints.Request(a=1, b=1), timeout_sec=5).sum == 2
    server.kill()
    wait_until(lambda: not client._route().is_set(), 10, message='the route to the killed server went')
    future = client.call_async(add_two_ints.Request())
    assert future.wait(5), 'the call waited for a server to come back'
    assert 'went away' in str(future.exception())


def test_a_call_with_no_server_ever_fails_with_one_line(context, add_two_ints):
    node = Node('hopeful', context=context)
    client = node.create_client(add_two_ints, 'nobody_ever')
    future = client.call_async(add_two_ints.Request(), timeout_sec=0.3)
    assert future.wait(5)
    assert isinstance(future.exception(), TimeoutError)
    assert 'no server appeared' in str(future.exception())
    assert client.call(add_two_ints.Request(), timeout_sec=0.3) is None


def test_a_call_to_a_slow_server_returns_none_after_its_timeout(make_context, add_two_ints):
    """rclpy's contract: call() gives None when no answer came in time (call_async's future
    carries the TimeoutError)."""
    server_ctx, client_ctx = make_context(), make_context()
    server = Node('slow_server', context=server_ctx)

    def slow(request, response):
        time.sleep(1.5)
        return response
    server.create_service(add_two_ints, 'slow', slow)
    executor = SingleThreadedExecutor(context=server_ctx)
    executor.add_node(server)
    threading.Thread(target=lambda: _spin_quietly(executor), daemon=True).start()
    _, client = _client(client_ctx, add_two_ints, 'slow')
    started = time.monotonic()
    assert client.call(add_two_ints.Request(), timeout_sec=0.5) is None
    assert time.monotonic() - started < 1.4
    executor.shutdown()


def test_server_killed_mid_call_fails_the_future(spawn, context, add_two_ints):
    script = spawn.script('''
import time, zros
from zros.node import Node
from interfaces.example_interfaces.srv import AddTwoInts
zros.init()
node = Node('doomed')
def handler(request, response):
    print('got request', flush=True)
    time.sleep(30)
    return response
node.create_service(AddTwoInts, 'doomed', handler)
zros.spin(node)
''', name='doomed')
    _, client = _client(context, add_two_ints, 'doomed')
    future = client.call_async(add_two_ints.Request())
    script.wait_for_output('got request')
    script.kill()
    assert future.wait(5.0), 'the call did not fail when the server died'
    assert isinstance(future.exception(), ServiceCallError)


def test_request_of_the_wrong_type_is_refused(context, server_process):
    from interfaces.std_srvs.srv import Trigger
    node = Node('confused', context=context)
    client = node.create_client(Trigger, 'add_two_ints')
    assert client.wait_for_service(timeout_sec=10)
    with pytest.raises(ServiceCallError, match='example_interfaces/srv/AddTwoInts'):
        client.call(Trigger.Request(), timeout_sec=5)
    with pytest.raises(TypeError, match='expects std_srvs/srv/Trigger'):
        client.call_async(object())


def test_custom_service_from_interface_path(tmp_path, monkeypatch, spawn, zros_cli):
    pkg = tmp_path / 'custom_srv_pkg' / 'srv'
    pkg.mkdir(parents=True)
    (pkg / 'CustomCalc.srv').write_text('int64 a\nint64 b\n---\nint64 result\n')
    monkeypatch.setenv('ZROS_INTERFACE_PATH', str(tmp_path))
    server = spawn.script('''
import zros
from zros.node import Node
from interfaces.custom_srv_pkg.srv import CustomCalc
zros.init()
node = Node('calc')
def handler(request, response):
    response.result = request.a * request.b
    return response
node.create_service(CustomCalc, 'calc', handler)
print('ready', flush=True)
zros.spin(node)
''', name='calc')
    server.wait_for_output('ready')
    result = zros_cli('service', 'call', '/calc', 'custom_srv_pkg/srv/CustomCalc', '{a: 6, b: 7}')
    assert result.returncode == 0, result
    assert 'response:\ncustom_srv_pkg.srv.CustomCalc_Response(result=42)\n' in result.stdout, result
    client = spawn.script('''
import zros
from zros.node import Node
from interfaces.custom_srv_pkg.srv import CustomCalc
zros.init()
node = Node('calc_client')
cli = node.create_client(CustomCalc, 'calc')
assert cli.wait_for_service(10)
print('answer', cli.call(CustomCalc.Request(a=3, b=5), timeout_sec=5).result, flush=True)
zros.shutdown()
''', name='calc_client')
    assert client.wait(timeout=20) == 0
    assert 'answer 15' in client.output()


def test_service_cli(server_process, zros_cli, context, add_two_ints):
    _client(context, add_two_ints)  # the server is up
    listed = zros_cli('service', 'list', '-t')
    assert '/add_two_ints [example_interfaces/srv/AddTwoInts]' in listed.stdout
    assert '/add_two_ints_server/get_parameters [rcl_interfaces/srv/GetParameters]' in listed.stdout
    assert zros_cli('service', 'type', '/add_two_ints').stdout.strip() == 'example_interfaces/srv/AddTwoInts'
    assert zros_cli('service', 'find', 'example_interfaces/srv/AddTwoInts').stdout.split() == ['/add_two_ints']
    call = zros_cli('service', 'call', '/add_two_ints', 'example_interfaces/srv/AddTwoInts', '{a: 2, b: 3}')
    assert call.returncode == 0, call
    assert 'requester: making request: example_interfaces.srv.AddTwoInts_Request(a=2, b=3)' in call.stdout
    assert 'response:\nexample_interfaces.srv.AddTwoInts_Response(sum=5)\n\n' in call.stdout, call  # ros2's repr form
    bad = zros_cli('service', 'call', '/add_two_ints', 'example_interfaces/srv/AddTwoInts', '{c: 1}')
    assert bad.returncode == 1 and "unknown field 'c'" in bad.stderr and 'Traceback' not in bad.stderr
    wrong = zros_cli('service', 'call', '/add_two_ints', 'std_srvs/srv/Trigger', '{}')
    assert wrong.returncode == 1 and 'is of type example_interfaces/srv/AddTwoInts' in wrong.stderr
    missing = zros_cli('service', 'call', '/nope', 'std_srvs/srv/Trigger', '{}', '--timeout', '0.5')
    assert missing.returncode == 1 and 'did not appear' in missing.stderr
    proto = zros_cli('interface', 'proto', 'example_interfaces/srv/AddTwoInts')
    assert proto.stdout.strip() == '"a: 0\nb: 0"'


def test_two_servers_on_one_name_are_reported(make_context, add_two_ints, capfd):
    first, second = Node('first', context=make_context()), Node('second', context=make_context())
    first.create_service(add_two_ints, 'shared', lambda req, resp: resp)
    time.sleep(0.2)
    second.create_service(add_two_ints, 'shared', lambda req, resp: resp)
    assert "service '/shared' is already served by /first" in capfd.readouterr().err
