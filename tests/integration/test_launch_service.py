"""LaunchService with real processes: launch descriptions included into a running launch, the
context's handlers seeing process start, output, exit and shutdown as launch's events, a
shutdown from another thread, and `zros launch` carrying out the same handlers (one runtime)."""
from __future__ import annotations

import sys
import threading
import time
from pathlib import Path

from conftest import run_cli
from unit.test_launch_parse import write  # noqa: F401 - the fixture
from zros.launch import EventHandler, LaunchDescription, LaunchService
from zros.launch.actions import ExecuteProcess, OpaqueFunction, RegisterEventHandler
from zros.launch.event_handlers import OnProcessIO
from zros.launch.events import Shutdown
from zros.launch.events.process import ProcessExited, ProcessStarted

PY = sys.executable


def recorder(seen: list, kind: type) -> RegisterEventHandler:
    """A generic handler whose OpaqueFunction records each event of `kind` it is given."""
    return RegisterEventHandler(EventHandler(
        matcher=lambda event: isinstance(event, kind),
        entities=OpaqueFunction(function=lambda context: seen.append(context.locals.event))))


def test_an_included_process_is_reported_as_launch_events_and_the_idle_launch_shuts_down():
    seen: list = []
    lines: list = []
    process = ExecuteProcess(cmd=[PY, '-c', 'print("hello from the child"); raise SystemExit(3)'])
    service = LaunchService()
    service.include_launch_description(LaunchDescription([
        recorder(seen, (ProcessStarted, ProcessExited, Shutdown)),
        RegisterEventHandler(OnProcessIO(target_action=process, on_stdout=lambda event: lines.append(event.text))),
        process,
    ]))
    assert service.run() == 0
    kinds = [type(event) for event in seen]
    assert kinds == [ProcessStarted, ProcessExited, Shutdown], seen
    assert seen[0].action is process and seen[1].returncode == 3 and seen[1].pid == seen[0].pid
    assert seen[2].reason == 'idle'
    assert b'hello from the child' in b''.join(lines)


def test_shutdown_from_another_thread_stops_a_running_process():
    seen: list = []
    service = LaunchService()
    service.include_launch_description(LaunchDescription([
        recorder(seen, ProcessExited),
        ExecuteProcess(cmd=[PY, '-c', 'import time; time.sleep(60)']),
    ]))
    threading.Timer(1.0, service.shutdown).start()
    began = time.monotonic()
    assert service.run(shutdown_when_idle=False) == 0
    assert time.monotonic() - began < 20
    assert len(seen) == 1 and seen[0].returncode != 0   # stopped by a signal, not finished


def test_zros_launch_offers_process_output_to_a_registered_on_process_io(write, tmp_path: Path):
    path = write('io.launch.py', f'''
        from launch import LaunchDescription
        from launch.actions import ExecuteProcess, LogInfo, RegisterEventHandler
        from launch.event_handlers import OnProcessIO

        def generate_launch_description():
            child = ExecuteProcess(cmd=[{PY!r}, '-c', 'print("ping")'])
            def answer(event):
                return [LogInfo(msg='heard ' + event.text.decode().strip())]
            return LaunchDescription([RegisterEventHandler(OnProcessIO(target_action=child, on_stdout=answer)),
                                      child])
    ''')
    result = run_cli('launch', str(path), '--log-dir', str(tmp_path / 'log'), timeout=60.0)
    assert result.returncode == 0, result
    assert 'heard ping' in result.stdout, result.stdout


def test_execution_complete_comes_after_an_action_runs_and_after_a_process_exits():
    from zros.launch.actions import LogInfo
    from zros.launch.event_handlers import OnExecutionComplete
    done: list = []
    log = LogInfo(msg='first')
    process = ExecuteProcess(cmd=[PY, '-c', 'pass'])
    service = LaunchService()
    service.include_launch_description(LaunchDescription([
        RegisterEventHandler(OnExecutionComplete(target_action=log, on_completion=lambda e, c: done.append('log'))),
        RegisterEventHandler(OnExecutionComplete(target_action=process,
                                                 on_completion=lambda e, c: done.append('process'))),
        log, process,
    ]))
    assert service.run() == 0
    assert done == ['log', 'process']


def test_an_entity_that_does_not_resolve_ends_the_launch_with_exit_code_1(capsys):
    """As launch: the error is logged and run() returns 1, the processes already started stop."""
    from zros.launch.actions import IncludeLaunchDescription
    from zros.launch.actions.arg import DeclareLaunchArgument
    from zros.launch.launch_description_sources import LaunchDescriptionSource
    service = LaunchService()
    service.include_launch_description(LaunchDescription([
        ExecuteProcess(cmd=[PY, '-c', 'import time; time.sleep(30)']),
        IncludeLaunchDescription(LaunchDescriptionSource(LaunchDescription([DeclareLaunchArgument('who')]))),
    ]))
    started = time.monotonic()
    assert service.run() == 1
    assert time.monotonic() - started < 20
    assert "Caught exception in launch: " in capsys.readouterr().out


def test_a_timer_kept_over_shutdown_fires_during_it_and_is_a_second_shutdown_event():
    from zros.launch.actions import Shutdown as ShutdownAction, TimerAction
    from zros.launch.event_handlers import OnShutdown
    reasons: list = []
    service = LaunchService()
    service.include_launch_description(LaunchDescription([
        ExecuteProcess(cmd=[PY, '-c', 'import time; time.sleep(30)']),
        TimerAction(period=0.5, actions=[ShutdownAction(reason='first')]),
        TimerAction(period=1.5, actions=[ShutdownAction(reason='kept')], cancel_on_shutdown=False),
        TimerAction(period=1.5, actions=[ShutdownAction(reason='cancelled')]),
        RegisterEventHandler(OnShutdown(on_shutdown=lambda event, context: reasons.append(event.reason))),
    ]))
    assert service.run() == 0
    assert reasons == ['first', 'kept']


def run_until_shutdown_due_to_sigint(noninteractive: bool) -> int:
    """The exit code of a process whose start emits Shutdown(due_to_sigint=True)."""
    from zros.launch.actions import EmitEvent
    from zros.launch.event_handlers import OnProcessExit, OnProcessStart
    codes: list = []
    process = ExecuteProcess(cmd=[PY, '-c', 'import time; time.sleep(30)'], sigterm_timeout='1')
    service = LaunchService(noninteractive=noninteractive)
    service.include_launch_description(LaunchDescription([
        process,
        RegisterEventHandler(OnProcessStart(target_action=process, on_start=[
            EmitEvent(event=Shutdown(reason='ctrl-c', due_to_sigint=True))])),
        RegisterEventHandler(OnProcessExit(target_action=process,
                                           on_exit=lambda event, context: codes.append(event.returncode))),
    ]))
    assert service.run() == 0
    return codes[0]


def test_shutdown_due_to_sigint_sends_sigint_only_when_noninteractive():
    import signal
    # interactive: the terminal's Ctrl-C is taken to have reached the process; SIGTERM follows
    assert run_until_shutdown_due_to_sigint(noninteractive=False) == -signal.SIGTERM
    assert run_until_shutdown_due_to_sigint(noninteractive=True) != -signal.SIGTERM


def exit_code_of(process: ExecuteProcess, *before) -> int:
    codes: list = []
    from zros.launch.event_handlers import OnProcessExit
    service = LaunchService()
    service.include_launch_description(LaunchDescription([
        *before, process,
        RegisterEventHandler(OnProcessExit(target_action=process,
                                           on_exit=lambda event, context: codes.append(event.returncode))),
    ]))
    assert service.run() == 0
    return codes[0]


def test_emulate_tty_gives_stdout_and_stderr_terminals_by_argument_or_configuration():
    from zros.launch.actions import SetLaunchConfiguration
    probe = [PY, '-c', 'import sys; print("seen"); sys.exit(sys.stdout.isatty() + 2 * sys.stderr.isatty())']
    assert exit_code_of(ExecuteProcess(cmd=probe)) == 0
    assert exit_code_of(ExecuteProcess(cmd=probe, emulate_tty=True)) == 3
    assert exit_code_of(ExecuteProcess(cmd=probe), SetLaunchConfiguration('emulate_tty', 'true')) == 3
    assert exit_code_of(ExecuteProcess(cmd=probe, emulate_tty=False), SetLaunchConfiguration('emulate_tty', 'true')) == 0


def _sleeper_launch(seen: list) -> LaunchService:
    """A launch of one process that never ends by itself, recording its exit."""
    service = LaunchService()
    service.include_launch_description(LaunchDescription([
        recorder(seen, ProcessExited),
        ExecuteProcess(cmd=[PY, '-c', 'import time; time.sleep(60)']),
    ]))
    return service


def test_run_async_leaves_the_loop_free_until_an_awaited_shutdown_stops_the_process():
    import asyncio
    seen: list = []
    service = _sleeper_launch(seen)
    assert service.shutdown() is None          # not running: nothing to shut down
    loop = asyncio.new_event_loop()
    ticks: list = []

    async def tick():
        # runs beside the launch only if run_async awaits between the supervisor's passes
        for _ in range(10):
            ticks.append(service.context.asyncio_loop)
            await asyncio.sleep(0.1)
    try:
        task = loop.create_task(service.run_async())
        loop.run_until_complete(tick())
        assert not task.done() and ticks == [loop] * 10
        shutdown = service.shutdown()            # on the loop's thread: a coroutine, as launch's
        assert asyncio.iscoroutine(shutdown)
        loop.create_task(shutdown)
        began = time.monotonic()
        assert loop.run_until_complete(task) == 0
        assert time.monotonic() - began < 20
    finally:
        loop.close()
    assert len(seen) == 1 and seen[0].returncode != 0    # stopped by a signal
    assert service.context.asyncio_loop is None


def test_run_async_stops_on_a_shutdown_from_another_thread():
    import asyncio
    seen: list = []
    service = _sleeper_launch(seen)
    answers: list = []
    threading.Timer(1.0, lambda: answers.append(service.shutdown())).start()
    loop = asyncio.new_event_loop()
    try:
        assert loop.run_until_complete(service.run_async(shutdown_when_idle=False)) == 0
    finally:
        loop.close()
    assert answers == [None] and len(seen) == 1 and seen[0].returncode != 0
