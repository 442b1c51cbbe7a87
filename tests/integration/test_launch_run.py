"""`zros launch` end to end: real supervisor and node processes on loopback, in a private
domain. Every wait has a timeout, and every process a test starts (the supervisor and each
child it reports) is killed at teardown."""
from __future__ import annotations

import os
import re
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest

from zros.config import hub_port_free
from zros.testing import wait_until

REPO = Path(__file__).resolve().parents[2]
PY = sys.executable


def _gone(pid: int) -> bool:
    """True when the process no longer runs (a zombie waiting for its reaper counts as gone)."""
    try:
        status = Path(f'/proc/{pid}/status').read_text()
    except (FileNotFoundError, ProcessLookupError):
        return True
    match = re.search(r'^State:\s+(\w)', status, re.M)
    return match is not None and match.group(1) in ('Z', 'X')


class Launch:
    """A `python -m zros launch FILE --log-dir DIR ...` process; stdout+stderr in one file."""

    def __init__(self, path: Path, args: list[str], directory: Path) -> None:
        self.log_dir = directory / 'logs'
        self.out_path = directory / 'launch.out'
        self._out = open(self.out_path, 'wb')
        self.argv = [PY, '-m', 'zros', 'launch', str(path), '--log-dir', str(self.log_dir), *args]
        self.popen = subprocess.Popen(self.argv, stdout=self._out, stderr=subprocess.STDOUT,
                                      stdin=subprocess.DEVNULL, cwd=REPO, start_new_session=True)
        self.seen_pids: set[int] = set()

    def output(self) -> str:
        return self.out_path.read_text(errors='replace')

    def pids(self) -> list[int]:
        found = [int(p) for p in re.findall(r'process started with pid \[(\d+)\]', self.output())]
        self.seen_pids.update(found)
        return found

    def wait_for(self, text: str, timeout: float = 20.0, count: int = 1) -> str:
        def found() -> bool:
            if self.output().count(text) >= count:
                return True
            if self.popen.poll() is not None and self.output().count(text) < count:
                pytest.fail(f'launch exited ({self.popen.returncode}) before printing {text!r} '
                            f'x{count}:\n{self.output()}')
            return False
        wait_until(found, timeout, message=lambda: f'{text!r} x{count}; output:\n{self.output()}')
        return self.output()

    def wait_exit(self, timeout: float) -> int:
        try:
            return self.popen.wait(timeout=timeout)
        except subprocess.TimeoutExpired:
            pytest.fail(f'launch still running after {timeout} s; output:\n{self.output()}')

    def kill(self) -> None:
        self.pids()
        for pid in [self.popen.pid, *self.seen_pids]:
            try:
                os.killpg(pid, signal.SIGKILL)
            except (ProcessLookupError, PermissionError):
                pass
        try:
            self.popen.wait(timeout=5)
        except subprocess.TimeoutExpired:  # pragma: no cover
            pass
        self._out.close()


@pytest.fixture
def launch(tmp_path: Path, domain: int):
    """`launch(yaml_text, *args)` starts a supervisor on a launch file written to tmp_path."""
    started: list[Launch] = []
    count = iter(range(1, 100))

    def start(text: str, *args: str) -> Launch:
        directory = tmp_path / f'run{next(count)}'
        directory.mkdir()
        path = directory / 'test.launch.yaml'
        path.write_text(textwrap.dedent(text).lstrip('\n'))
        process = Launch(path, list(args), directory)
        started.append(process)
        return process
    yield start
    for process in started:
        process.kill()


def _graph(context):
    from zros.graph import fetch_entities
    return fetch_entities(context.session, context.domain_id, timeout=1.0)


# -- the main scenario: nodes, namespaces, remaps, parameters, then Ctrl-C -------------------------
def test_launch_nodes_graph_params_and_sigint(launch, make_context, zros_cli):
    run = launch('''
        launch:
        - arg: {name: topic, default: news}
        - group:
          - push_ros_namespace: {namespace: robot}
          - node: {pkg: demo_nodes, exec: talker, name: talker, remap: [{from: chatter, to: $(var topic)}]}
          - node: {pkg: demo_nodes, exec: listener, name: ears, remap: [{from: chatter, to: $(var topic)}]}
        - node:
            pkg: demo_nodes
            exec: param_talker
            name: param_talker
            param:
            - from: $(find-pkg-share configs)/params/talker.yaml
            - {name: published_text, value: "from the launch file"}
            remap: [{from: chatter, to: /robot/$(var topic)}]
        ''')
    run.wait_for('process started with pid', count=3)
    assert not hub_port_free(int(os.environ['ZROS_DOMAIN_ID'])), 'the supervisor should be the hub'
    context = make_context()
    expected = {'/robot/talker', '/robot/ears', '/param_talker'}

    def endpoints(entities, kind):
        return {e.node_fqn for e in entities if e.kind == kind and e.name == '/robot/news'}

    def graph_complete():
        entities = _graph(context)
        names = {e.node_fqn for e in entities if e.kind == 'NN'}
        ready = expected <= names and endpoints(entities, 'MP') >= {'/robot/talker', '/param_talker'} \
            and endpoints(entities, 'MS') >= {'/robot/ears'}
        return entities if ready else None
    entities = wait_until(graph_complete, 25, message=lambda: f'nodes {expected}; output:\n{run.output()}')
    assert endpoints(entities, 'MP') == {'/robot/talker', '/param_talker'}
    assert endpoints(entities, 'MS') == {'/robot/ears'}
    assert not any(e.name in ('/chatter', '/robot/chatter') for e in entities)

    text = zros_cli('param', 'get', '/param_talker', 'published_text')
    assert text.stdout.strip() == 'String value is: from the launch file', text
    period = zros_cli('param', 'get', '/param_talker', 'timer_period')
    assert period.stdout.strip() == 'Double value is: 0.5', period     # from the parameter file

    run.wait_for("[talker-1] [INFO]", timeout=15)        # stderr reaches the screen with output: log
    out = run.output()
    assert re.search(r"\[talker-1\] \[INFO\] \[[\d.]+\] \[robot\.talker\]: Publishing: 'Hello World: \d+'", out), out
    pids = run.pids()
    assert len(pids) == 3

    started = time.monotonic()
    run.popen.send_signal(signal.SIGINT)
    assert run.wait_exit(10) == 0
    wait_until(lambda: all(_gone(pid) for pid in pids), 1.0, message='children gone')
    assert time.monotonic() - started < 5.0
    out = run.output()
    for name, pid in zip(('talker-1', 'listener-2', 'param_talker-3'), pids):
        assert f"[INFO] [{name}]: sending signal 'SIGINT' to process[{name}]" in out
        assert f'[INFO] [{name}]: process has finished cleanly [pid {pid}]' in out

    # no stale graph entries: the nodes' tokens left with them
    wait_until(lambda: not any(e.node_fqn in expected for e in _graph(context)), 3,
               message='the launched nodes to leave the graph')

    logs = run.log_dir
    assert {'launch.log', 'talker-1.log', 'listener-2.log', 'param_talker-3.log'} <= {p.name for p in logs.iterdir()}
    assert 'process started with pid' in (logs / 'launch.log').read_text()
    assert 'Publishing' in (logs / 'talker-1.log').read_text()
    generated = (logs / 'params' / 'param_talker-3.yaml').read_text()
    assert 'published_text: from the launch file' in generated


# -- respawn, on_exit, timers, escalation ------------------------------------------------------
def test_respawn_of_a_crashing_process(launch):
    run = launch(f'''
        launch:
        - executable:
            cmd: {PY} -c "import sys; print('boom'); sys.exit(1)"
            name: crasher
            output: screen
            respawn: true
            respawn_delay: 0.1
            respawn_max_retries: 2
        ''')
    assert run.wait_exit(30) == 0        # nothing left to run: the launch ends by itself
    out = run.output()
    assert out.count('[INFO] [crasher-1]: process started with pid') == 3, out
    assert out.count('[crasher-1] boom') == 3, out
    died = re.findall(r"\[ERROR\] \[crasher-1\]: process has died \[pid \d+, exit code 1, cmd '(.*)'\]\.", out)
    assert len(died) == 3 and 'sys.exit(1)' in died[0]
    assert (run.log_dir / 'crasher-1.log').read_text().count('boom') == 3


def test_on_exit_shutdown_timer_and_log(launch):
    run = launch(f'''
        launch:
        - executable: {{cmd: sleep 60, name: sleeper}}
        - log: {{message: "waiting for the timer"}}
        - timer:
            period: 0.3
            children:
            - log: {{message: "timer fired"}}
            - executable:
                cmd: {PY} -c "import time; time.sleep(0.2)"
                name: short
                on_exit: shutdown
        ''')
    assert run.wait_exit(20) == 0
    out = run.output()
    lines = out.splitlines()
    order = [next(i for i, line in enumerate(lines) if text in line) for text in (
        '[INFO] [sleeper-1]: process started', '[INFO] [launch.user]: waiting for the timer',
        '[INFO] [launch.user]: timer fired', '[INFO] [short-2]: process started',
        '[INFO] [short-2]: process has finished cleanly',
        '[INFO] [launch]: shutting down: process[short-2] exited and has on_exit: shutdown',
        "[INFO] [sleeper-1]: sending signal 'SIGINT' to process[sleeper-1]")]
    assert order == sorted(order), out
    assert re.search(r"\[ERROR\] \[sleeper-1\]: process has died \[pid \d+, exit code -2, cmd 'sleep 60'\]", out)
    assert all(_gone(pid) for pid in run.pids())


def test_output_modes_and_log_files(launch):
    modes = ('log', 'screen', 'both', 'own_log')
    text = 'launch:\n' + ''.join(
        f'- executable:\n'
        f'    cmd: {PY} -c "import sys; print(\'OUT-{m}\'); print(\'ERR-{m}\', file=sys.stderr)"\n'
        f'    name: {m}\n    output: {m}\n' for m in modes)
    run = launch(text)
    assert run.wait_exit(20) == 0
    screen = run.output()
    launch_log = (run.log_dir / 'launch.log').read_text()
    expected_screen = {'log': {'ERR'}, 'screen': {'OUT', 'ERR'}, 'both': {'OUT', 'ERR'}, 'own_log': set()}
    for number, mode in enumerate(modes, start=1):
        name = f'{mode}-{number}'
        shown = {kind for kind in ('OUT', 'ERR') if f'[{name}] {kind}-{mode}' in screen}
        assert shown == expected_screen[mode], (mode, screen)
        logged = {kind for kind in ('OUT', 'ERR') if f'[{name}] {kind}-{mode}' in launch_log}
        assert logged == (set() if mode == 'own_log' else {'OUT', 'ERR'}), (mode, launch_log)
        assert sorted((run.log_dir / f'{name}.log').read_text().split()) == [f'ERR-{mode}', f'OUT-{mode}']


def test_sigint_escalates_to_sigterm_and_sigkill(launch):
    ignore_int = 'import signal, time; signal.signal(signal.SIGINT, signal.SIG_IGN)'
    ignore_both = ignore_int + '; signal.signal(signal.SIGTERM, signal.SIG_IGN)'
    run = launch(f'''
        launch:
        - executable:
            cmd: {PY} -c "{ignore_int}; print('ready', flush=True); time.sleep(60)"
            name: stubborn
            output: screen
            sigterm_timeout: 0.3
        - executable:
            cmd: {PY} -c "{ignore_both}; print('ready', flush=True); time.sleep(60)"
            name: very_stubborn
            output: screen
            sigterm_timeout: 0.3
            sigkill_timeout: 0.3
        ''')
    run.wait_for('] ready', count=2)
    pids = run.pids()
    started = time.monotonic()
    run.popen.send_signal(signal.SIGINT)
    assert run.wait_exit(10) == 0
    assert time.monotonic() - started < 5.0
    out = run.output()
    assert ("[ERROR] [stubborn-1]: process[stubborn-1] failed to terminate '0.3' seconds after receiving "
            "'SIGINT', escalating to 'SIGTERM'") in out
    assert "escalating to 'SIGKILL'" in out and 'very_stubborn-2' in out
    assert re.search(r'very_stubborn-2\]: process has died \[pid \d+, exit code -9', out), out
    assert all(_gone(pid) for pid in pids)


def test_sigkill_of_the_supervisor_leaves_no_orphans(launch):
    run = launch('''
        launch:
        - node: {pkg: demo_nodes, exec: talker}
        - executable: {cmd: sleep 60}
        ''')
    run.wait_for('process started with pid', count=2)
    pids = run.pids()
    assert not any(_gone(pid) for pid in pids)
    run.popen.send_signal(signal.SIGKILL)
    run.wait_exit(5)
    wait_until(lambda: all(_gone(pid) for pid in pids), 2.0,
               message=lambda: f'children {pids} to die with the supervisor')


# -- the command line ----------------------------------------------------------------------------
def _bad_file(tmp_path: Path) -> Path:
    path = tmp_path / 'bad.launch.yaml'
    path.write_text('launch:\n- node: {pkg: demo_nodes, exec: talker}\n- node:\n    pkg: demo_nodes\n'
                    '    exec: talkr\n')
    return path


def test_bad_files_are_rejected_with_file_and_line(tmp_path, domain, zros_cli):
    result = zros_cli('launch', str(_bad_file(tmp_path)), '--log-dir', str(tmp_path / 'logs'))
    assert result.returncode == 1, result
    assert 'process started' not in result.stdout and 'Traceback' not in result.stderr
    line, = result.stderr.strip().splitlines()
    assert line.startswith(f'{tmp_path}/bad.launch.yaml:5: node: exec: no executable \'talkr\''), line
    assert not (tmp_path / 'logs').exists()
    syntax = tmp_path / 'syntax.launch.yaml'
    syntax.write_text('launch:\n- node: {pkg: demo_nodes\n')
    result = zros_cli('launch', str(syntax))
    assert result.returncode == 1 and re.fullmatch(rf'{re.escape(str(syntax))}:3: invalid YAML: .*\n', result.stderr)
    result = zros_cli('launch', str(REPO / 'configs' / 'talker_listener.launch.yaml'), 'tpoic:=x')
    assert result.returncode == 1 and "unknown launch argument 'tpoic' (declared arguments: topic)" in result.stderr
    result = zros_cli('launch', 'no_such_file.launch.yaml')
    assert result.returncode == 1 and "no such launch file 'no_such_file.launch.yaml'" in result.stderr


def test_print_and_show_args_start_nothing(tmp_path, domain, zros_cli):
    result = zros_cli('launch', 'zros', 'talker_listener.launch.yaml', '--print', 'topic:=news',
                     '--log-dir', str(tmp_path / 'logs'))
    assert result.returncode == 0, result
    assert f'{PY} -m zros run demo_nodes talker --ros-args -r chatter:=news' in result.stdout
    assert 'process [listener-2]' in result.stdout and 'process started' not in result.stdout
    assert not (tmp_path / 'logs').exists()
    shown = zros_cli('launch', 'configs/talker_listener.launch.yaml', '--show-args')
    assert shown.returncode == 0, shown
    assert shown.stdout.splitlines()[:5] == [
        "Arguments (pass arguments as '<name>:=<value>'):", '', "    'topic':",
        '        Topic the talker publishes and the listener subscribes to', "        (default: 'chatter')"]
    params = zros_cli('launch', 'configs', 'params_demo.launch.yaml', '-p')
    assert 'published_text: Hello from params_demo.launch.yaml' in params.stdout
    assert '/configs/params/talker.yaml' in params.stdout


ON_SHUTDOWN = '''
import os
from launch import LaunchDescription
from launch.actions import ExecuteProcess, LogInfo, RegisterEventHandler
from launch.event_handlers import OnShutdown


def generate_launch_description():
    marker = os.path.join(os.path.dirname(__file__), 'generated.sdf')
    open(marker, 'w').close()
    return LaunchDescription([
        ExecuteProcess(cmd=['sleep', '60'], name='sleeper'),
        RegisterEventHandler(OnShutdown(on_shutdown=[LogInfo(msg='bye from actions')])),
        # turtlebot3_gazebo's multi_robot.launch.py cleans up this way: a list of None
        RegisterEventHandler(OnShutdown(on_shutdown=lambda event, context: [os.remove(marker)])),
        RegisterEventHandler(OnShutdown(on_shutdown=lambda event, context: LogInfo(msg='why: ' + event.reason))),
    ])
'''


def test_on_shutdown_handlers_run_when_the_launch_stops(tmp_path: Path, domain: int):
    path = tmp_path / 'cleanup.launch.py'
    path.write_text(ON_SHUTDOWN)
    run = Launch(path, [], tmp_path)
    try:
        run.wait_for('process started with pid')
        assert (tmp_path / 'generated.sdf').exists()
        os.killpg(run.popen.pid, signal.SIGINT)
        assert run.wait_exit(15) == 0
        out = run.output()
        assert '[INFO] [launch.user]: bye from actions' in out, out
        assert '[INFO] [launch.user]: why: user interrupted with ctrl-c (SIGINT)' in out, out
        assert not (tmp_path / 'generated.sdf').exists()
        assert out.index('bye from actions') < out.index("sending signal 'SIGINT' to process[sleeper-1]")
    finally:
        run.kill()
