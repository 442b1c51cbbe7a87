"""SIGINT and SIGTERM stop zros programs and CLI verbs however they were started (issue 23).

A shell without job control (a script's `cmd &`) and nohup start programs with SIGINT
*ignored*; every scenario here runs its process that way, through `_ignoring_sigint`, so the
handlers zros installs are what makes them stop.
"""
from __future__ import annotations

import signal
import sys
import time

import pytest

from zros.executors import SingleThreadedExecutor
from zros.node import Node

from interfaces.std_msgs.msg import String

# Exec the command with SIGINT ignored, as a background job of a non-interactive shell has it.
_SHIM = ('import os, signal, sys; signal.signal(signal.SIGINT, signal.SIG_IGN); '
         'os.execv(sys.argv[1], sys.argv[1:])')


def _ignoring_sigint(*argv: str) -> list[str]:
    return [sys.executable, '-c', _SHIM, *argv]


def _zros(*args: str) -> list[str]:
    return _ignoring_sigint(sys.executable, '-m', 'zros', *args)


def _stops(child, signum: int = signal.SIGINT, timeout: float = 10.0) -> int:
    """Send `signum`; the exit status (the test fails if the process outlives `timeout`)."""
    child.signal(signum)
    try:
        code = child.wait(timeout)
    except Exception:  # noqa: BLE001 - report what the process printed
        pytest.fail(f'{child.argv[-3:]} still running {timeout} s after {signum!r}:\n{child.output()}')
    assert 'Traceback' not in child.output(), child.output()
    return code


# -- nodes --------------------------------------------------------------------------------------
@pytest.mark.parametrize('executable', ['talker', 'listener'])
@pytest.mark.parametrize('signum', [signal.SIGINT, signal.SIGTERM], ids=['SIGINT', 'SIGTERM'])
def test_a_node_started_with_sigint_ignored_stops(spawn, zros_cli, executable, signum):
    child = spawn(*_zros('run', 'demo_nodes', executable), name=executable)
    result = zros_cli('node', 'list')
    deadline = time.monotonic() + 15
    while f'/{executable}' not in result.stdout and time.monotonic() < deadline:
        time.sleep(0.2)
        result = zros_cli('node', 'list')
    assert f'/{executable}' in result.stdout, child.output()
    assert _stops(child, signum) == 0


SCRIPT_HEAD = '''
import signal, sys, threading, time
import zros
from zros.executors import ExternalShutdownException
'''


def test_sigint_raises_keyboard_interrupt_and_cleanup_can_still_publish(context, spawn, wait_for):
    """The program gets KeyboardInterrupt with its nodes intact: a teleop's stop command in its
    cleanup still goes out."""
    from zros.node import Node
    from interfaces.std_msgs.msg import String
    heard = []
    Node('last_words_listener', context=context).create_subscription(
        String, '/last_words', lambda msg: heard.append(msg.data), 10)
    from zros.executors import SingleThreadedExecutor
    child = spawn(*_ignoring_sigint(sys.executable, '-c', SCRIPT_HEAD + '''
from interfaces.std_msgs.msg import String
zros.init()
node = zros.create_node('plain')
publisher = node.create_publisher(String, '/last_words', 10)
print('spinning', flush=True)
try:
    zros.spin(node)
except KeyboardInterrupt:
    publisher.publish(String(data=f'stop (ok() is {zros.ok()})'))
zros.shutdown()
'''), name='spin')
    child.wait_for_output('spinning')
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(next(iter(context._nodes)))
    wait_for(lambda: context.graph and any(e.node_fqn == '/plain' and e.name == '/last_words'
                                           for e in context.graph.entities()), timeout=10)
    time.sleep(0.2)
    assert _stops(child) == 0
    deadline = time.monotonic() + 5
    while not heard and time.monotonic() < deadline:
        executor.spin_once(timeout_sec=0.1)
    assert heard == ['stop (ok() is True)'], child.output()


def test_sigterm_ends_a_spin_in_another_thread(spawn):
    """As rclpy: the signal shuts the context down, so a spin anywhere ends."""
    child = spawn(*_ignoring_sigint(sys.executable, '-c', SCRIPT_HEAD + '''
zros.init()
node = zros.create_node('threaded')
ended = []
def spin():
    try:
        zros.spin(node)
    except ExternalShutdownException:
        ended.append('ExternalShutdownException')
thread = threading.Thread(target=spin)
thread.start()
print('spinning', flush=True)
while zros.ok():
    time.sleep(0.01)
thread.join(5)
print('spin ended with', ended, flush=True)
'''), name='threaded')
    child.wait_for_output('spinning')
    assert _stops(child, signal.SIGTERM) == 0
    assert "spin ended with ['ExternalShutdownException']" in child.output()


def test_sigterm_while_a_node_is_being_built_stops_it_quietly(spawn, tmp_path, monkeypatch):
    """A launch may stop a node before its constructor has finished (it is in the graph
    already): the entities it creates after the signal meet a closed session, and `zros run`
    ends it without a traceback."""
    (tmp_path / 'starting').mkdir()
    (tmp_path / 'starting' / 'slow_node.py').write_text(SCRIPT_HEAD + '''
from interfaces.std_msgs.msg import String
from interfaces.std_srvs.srv import Empty


def main():
    zros.init()
    node = zros.create_node('slow_node')
    print('building', flush=True)
    time.sleep(1.0)   # the rest of a long constructor; SIGTERM arrives meanwhile
    node.create_subscription(String, 'chatter', print, 10)
    node.create_service(Empty, 'reset', lambda request, response: response)
    zros.spin(node)
''')
    monkeypatch.setenv('ZROS_NODE_PATH', str(tmp_path))
    child = spawn(*_zros('run', 'starting', 'slow_node'), name='slow_node')
    child.wait_for_output('building', timeout=15)
    assert _stops(child, signal.SIGTERM) == 0


def test_a_handler_installed_before_init_is_still_called(spawn):
    child = spawn(*_ignoring_sigint(sys.executable, '-c', SCRIPT_HEAD + '''
signal.signal(signal.SIGINT, lambda signum, frame: print('own handler', flush=True))
zros.init()
node = zros.create_node('chained')
print('spinning', flush=True)
try:
    zros.spin(node)
except ExternalShutdownException:
    print('external shutdown', flush=True)
'''), name='chained')
    child.wait_for_output('spinning')
    assert _stops(child) == 0
    assert 'own handler' in child.output() and 'external shutdown' in child.output()


def test_signal_handler_options_no_keeps_the_inherited_disposition(spawn):
    child = spawn(*_ignoring_sigint(sys.executable, '-c', SCRIPT_HEAD + '''
from zros.signals import SignalHandlerOptions, get_current_signal_handlers_options
zros.init(signal_handler_options=SignalHandlerOptions.NO)
print('options', get_current_signal_handlers_options().name, flush=True)
node = zros.create_node('opted_out')
print('spinning', flush=True)
zros.spin(node)
'''), name='opted_out')
    child.wait_for_output('spinning')
    assert 'options NO' in child.output()
    child.signal(signal.SIGINT)            # ignored, as the program asked
    time.sleep(1.0)
    assert child.popen.poll() is None, child.output()
    child.signal(signal.SIGTERM)           # Python's default: the process dies of it
    assert child.wait(10) == -signal.SIGTERM


def test_a_main_thread_stuck_in_native_code_still_exits(spawn):
    """The main thread blocks inside Zenoh without the GIL and never returns to the interpreter
    (a FIFO reply channel that nobody drains); the signal watcher ends the process."""
    child = spawn(*_ignoring_sigint(sys.executable, '-c', SCRIPT_HEAD + '''
ctx = zros.init()
tokens = [ctx.session.liveliness().declare_token(f'zros_stuck_test/{i}') for i in range(400)]
print('blocking', flush=True)
list(ctx.session.liveliness().get('zros_stuck_test/**', timeout=1))
print('never reached', flush=True)
'''), name='stuck')
    child.wait_for_output('blocking')
    time.sleep(0.3)
    started = time.monotonic()
    assert _stops(child) == 1
    assert time.monotonic() - started < 2 + 3, 'the stuck-main-thread deadline is 2 s'
    assert 'never reached' not in child.output()


# -- command-line verbs ---------------------------------------------------------------------------
@pytest.mark.parametrize('argv, ready', [
    (('topic', 'echo', '/quiet', 'std_msgs/msg/String'), None),
    (('topic', 'hz', '/quiet'), 'does not appear to be published yet'),
    (('topic', 'pub', '/quiet', 'std_msgs/msg/String', '{data: hi}', '--rate', '2'), 'beginning loop'),
    (('service', 'call', '/absent', 'std_srvs/srv/Empty'), 'waiting for service'),
    (('action', 'send_goal', '/absent', 'action_tutorials_interfaces/action/Fibonacci', '{order: 3}'),
     'Waiting for an action server'),
], ids=['topic-echo', 'topic-hz', 'topic-pub', 'service-call', 'action-send_goal'])
def test_waiting_cli_verbs_exit_on_ctrl_c(context, spawn, wait_for, argv, ready):
    child = spawn(*_zros(*argv), name=argv[0])
    if ready is None:   # echo prints nothing while it waits: its subscription shows it is up
        watcher = Node('echo_watcher', context=context)
        wait_for(lambda: watcher.count_subscribers('/quiet') >= 1, timeout=15, message=child.output)
    else:
        child.wait_for_output(ready, timeout=15)
    assert _stops(child, timeout=5) == 130


def test_bag_record_finishes_its_file_on_ctrl_c(spawn, tmp_path):
    bag = tmp_path / 'ctrl_c_bag'
    child = spawn(*_zros('bag', 'record', '-a', '-o', str(bag)), name='record')
    child.wait_for_output('Recording to', timeout=15)
    assert _stops(child, timeout=10) == 0
    assert 'Recorded' in child.output()


def test_bag_play_stops_on_ctrl_c(context, spawn, spin_for, tmp_path):
    from zros.bag.writer import BagWriter
    from zros.message import serialize
    bag = tmp_path / 'looped'
    with BagWriter(bag) as writer:
        writer.add_topic('/looped', 'std_msgs/msg/String', type_hash=String._HASH, qos='R:V:L10')
        for i in range(20):   # 20 messages 0.1 s apart, played again and again
            t = 1_700_000_000_000_000_000 + i * 100_000_000
            writer.write('/looped', serialize(String(data=f'm{i}')), log_time=t, publish_time=t)
    heard = []
    watcher = Node('play_watcher', context=context)
    watcher.create_subscription(String, '/looped', heard.append, 10)
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(watcher)
    child = spawn(*_zros('bag', 'play', '--loop', str(bag)), name='play')
    spin_for(executor, lambda: len(heard) > 20, timeout=15)   # into its second round
    assert child.popen.poll() is None, child.output()
    assert _stops(child, timeout=5) == 0


def test_launch_children_get_default_signals_and_stop(spawn, tmp_path):
    """The launch inherits SIGINT ignored; its children must not, or they would ignore its SIGINT."""
    probe = tmp_path / 'probe.py'
    probe.write_text('import signal, time\n'
                     'print("child SIGINT is", signal.getsignal(signal.SIGINT).__name__, flush=True)\n'
                     'try:\n    time.sleep(60)\nexcept KeyboardInterrupt:\n    print("interrupted", flush=True)\n')
    launch_file = tmp_path / 'probe.launch.yaml'
    launch_file.write_text(f'launch:\n- executable: {{cmd: "{sys.executable} {probe}", name: probe, output: screen}}\n')
    child = spawn(*_zros("launch", str(launch_file), "--log-dir", str(tmp_path / "logs")), name="launch")
    child.wait_for_output('child SIGINT is', timeout=15)
    assert 'child SIGINT is default_int_handler' in child.output()
    assert _stops(child, timeout=10) == 0
    out = child.output()
    assert "sending signal 'SIGINT'" in out and '[probe-1] interrupted' in out and 'SIGTERM' not in out
