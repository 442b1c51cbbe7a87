"""Running one launch test: the launch under zros's supervisor, its tests alongside.

As launch_testing does, the launch runs on the main thread (the supervisor must: it handles
signals and forks the children) and the active tests on a thread of their own, started when the
launch reaches ReadyToTest; when they are done the launch is shut down, and the post-shutdown
tests run on the main thread with every exit code known.

Two things zros adds:
- the test runs in a private zros domain (zros.testing.domains), so tests running at the same
  time, or a robot on the same machine, never see each other;
- ReadyToTest also waits (within the ready timeout) until every node started before it is in
  the graph, and zros is initialized for the tests' process (provisionally: a test's own
  `rclpy.init()` replaces it), so a test that creates a node and calls a service at once works.
"""
from __future__ import annotations

import sys
import threading
import time
import unittest
from pathlib import Path
from typing import Any, TextIO

from zros.launch.description import resolve_actions
from zros.launch.plan import CallEffect, ProcessSpec
from zros.launch.supervisor import ProcessObserver, Supervisor
from zros.launch_testing.handlers import (ActiveIoHandler, ActiveProcInfoHandler, ProcessExited, ProcessIO,
                                          ProcessStarted)
from zros.launch_testing.loader import LaunchTest
from zros.launch_testing.util import ProcessDetails

__all__ = ['run_launch_test', 'LaunchTestOutcome', 'LaunchService']

_SHOWN_LINES = 10   # of each failed process's output, when the launch ends early


class LaunchTestOutcome:
    """The results of one launch test: the active and post-shutdown unittest results, and
    `problem`, a sentence when the launch itself went wrong (ReadyToTest never reached, the
    launch ended before the active tests did)."""

    def __init__(self, name: str) -> None:
        self.name = name
        self.active: unittest.TestResult | None = None
        self.post_shutdown: unittest.TestResult | None = None
        self.problem: str | None = None

    @property
    def ok(self) -> bool:
        results = [r for r in (self.active, self.post_shutdown) if r is not None]
        return self.problem is None and all(r.wasSuccessful() for r in results)

    def failures(self) -> list[tuple[str, str]]:
        """(what failed, why) for each failed test, and for the launch's problem."""
        found = [(self.name, self.problem)] if self.problem else []
        for result in (self.active, self.post_shutdown):
            if result is not None:
                found += [(test.id(), text) for test, text in result.errors + result.failures]
                found += [(test.id(), 'unexpected success') for test in result.unexpectedSuccesses]
        return found


class LaunchService:
    """What tests get as `launch_service`: a way to end the launch early."""

    def __init__(self, supervisor: Supervisor) -> None:
        self._supervisor = supervisor

    def shutdown(self, reason: str = 'shut down by a test') -> None:
        self._supervisor.request_shutdown(reason)

    def emit_event(self, event: Any) -> None:
        """launch's way to shut down: `emit_event(launch.events.Shutdown())`."""
        from zros.launch.events import Shutdown
        if not isinstance(event, Shutdown):
            raise TypeError(f'zros launch tests can emit launch.events.Shutdown only, not {type(event).__name__}')
        self.shutdown(str(event.reason or 'shut down by a test'))


class _Recorder(ProcessObserver):
    """Feeds proc_info and proc_output from the supervisor's thread."""

    def __init__(self) -> None:
        self.proc_info = ActiveProcInfoHandler()
        self.proc_output = ActiveIoHandler()
        self.node_processes = 0     # started so far: ReadyToTest waits for that many nodes
        self.exited_nodes = 0

    def started(self, name: str, spec: ProcessSpec, pid: int, cmd: list[str]) -> None:
        details = ProcessDetails(name, spec.source, list(cmd))
        self.proc_output.track(details)
        self.proc_info.track(details)
        self.proc_info.append(ProcessStarted(spec.source, name, pid, list(cmd)))
        self.node_processes += spec.node is not None

    def output(self, name: str, spec: ProcessSpec, is_stderr: bool, lines: list[str]) -> None:
        text = ''.join(line + '\n' for line in lines).encode()
        self.proc_output.append(ProcessIO(name, spec.source, text, 2 if is_stderr else 1))

    def exited(self, name: str, spec: ProcessSpec, pid: int, returncode: int, cmd: list[str]) -> None:
        self.proc_info.append(ProcessExited(spec.source, name, pid, list(cmd), returncode))
        self.exited_nodes += spec.node is not None

    def failed_processes(self) -> str:
        """Each process that exited with an error, with its last lines of output."""
        text = ''
        for event in self.proc_info._handler:
            if isinstance(event, ProcessExited) and event.returncode != 0:
                lines = ''.join(io.text.decode(errors='replace') for io in self.proc_output[event.process_name])
                shown = ''.join(f'\n    {line}' for line in lines.splitlines()[-_SHOWN_LINES:])
                text += f'\n  {event.process_name} exited with {event.returncode}' + (f':{shown}' if shown else '')
        return text


class _Run:
    """One run of a LaunchTest (the state its two threads share)."""

    def __init__(self, test: LaunchTest, launch_arguments: dict[str, str], log_dir: Path, screen: TextIO | None,
                 stream: TextIO, debug: bool) -> None:
        self.test = test
        self.stream = stream
        self.outcome = LaunchTestOutcome(test.name)
        self.recorder = _Recorder()
        self.ready = threading.Event()
        self.ready_nodes = 0
        self.launch_over = False
        self.tests_done = threading.Event()
        description, values = test.describe(self._on_ready)
        early = self.ready.is_set()   # an old-style ready_fn, called while the description was built
        self.ready.clear()
        plan = resolve_actions(description.entities, test.path, launch_arguments=launch_arguments,
                               log_dir=str(log_dir))
        if early or self.ready.is_set():   # or called from an OpaqueFunction while resolving
            self.ready.clear()
            plan.effects.append(CallEffect('ready to test', self._on_ready))
        self.supervisor = Supervisor(plan, log_dir=log_dir, debug=debug, screen=screen, observer=self.recorder,
                                     keep_alive=test.keep_alive)
        test_args = dict(launch_arguments)
        common = {**values, 'test_args': test_args}
        test.bind(test.active_tests, {**common, 'proc_output': self.recorder.proc_output,
                                      'proc_info': self.recorder.proc_info,
                                      'launch_service': LaunchService(self.supervisor)})
        test.bind(test.post_shutdown_tests, {**common, 'proc_output': self.recorder.proc_output._handler,
                                             'proc_info': self.recorder.proc_info._handler})

    def _on_ready(self) -> None:
        self.ready_nodes = self.recorder.node_processes
        self.ready.set()

    def run(self) -> LaunchTestOutcome:
        tests = threading.Thread(target=self._run_active_tests, name='launch-test-active', daemon=True)
        tests.start()
        try:
            self.supervisor.run()
        finally:
            self.launch_over = True
            self.ready.set()
        if not self.tests_done.wait(timeout=0):
            self.outcome.problem = self.outcome.problem or (
                'the launch ended (no process left running) before the active tests finished'
                + self.recorder.failed_processes())
            tests.join(timeout=self.test.ready_timeout)
            return self.outcome
        tests.join()
        if self.outcome.problem is None and self.test.post_shutdown_tests.countTestCases():
            self.outcome.post_shutdown = _run_suite(self.test.post_shutdown_tests, self.stream)
        return self.outcome

    def _run_active_tests(self) -> None:
        """The test thread: wait for ReadyToTest, run the active tests, end the launch."""
        from zros.context import get_default_context
        context = get_default_context()
        ours = not context.ok()
        try:
            deadline = time.monotonic() + self.test.ready_timeout
            if not self.ready.wait(self.test.ready_timeout):
                self.outcome.problem = (f'the launch did not reach ReadyToTest within {self.test.ready_timeout:g} s'
                                        + self.recorder.failed_processes())
                return
            if self.launch_over:
                return
            self._wait_for_nodes(deadline)
            if ours:
                context.init([], install_signal_handlers=False, provisional=True)
            self.outcome.active = _run_suite(self.test.active_tests, self.stream)
        except Exception as exc:  # noqa: BLE001 - reported as the launch test's failure, not lost on a thread
            self.outcome.problem = f'{type(exc).__name__}: {exc}'
        finally:
            if ours and context.ok():
                import zros
                zros.shutdown(context=context)
            self.tests_done.set()
            self.supervisor.request_shutdown('the tests are done')

    def _wait_for_nodes(self, deadline: float) -> None:
        """Until the graph holds as many nodes as node processes were started before ReadyToTest
        (less those that exited), or the deadline: the tests' own waits take over then."""
        from zros.graph import EntityKind
        context = self.supervisor.context
        if context is None:
            return

        def enough(entities: list) -> bool:
            nodes = {e.node_key for e in entities if e.kind == EntityKind.NODE}
            return len(nodes) >= self.ready_nodes - self.recorder.exited_nodes
        while not self.launch_over and time.monotonic() < deadline:
            if context.graph.wait_for(enough, min(0.25, max(0.0, deadline - time.monotonic()))):
                return


def _run_suite(suite: unittest.TestSuite, stream: TextIO) -> unittest.TestResult:
    return unittest.TextTestRunner(stream=stream, verbosity=2).run(suite)


def run_launch_test(test: LaunchTest, *, log_dir: Path, launch_arguments: dict[str, str] | None = None,
                    screen: TextIO | None = None, stream: TextIO | None = None,
                    debug: bool = False) -> LaunchTestOutcome:
    """Run a launch test in a private zros domain; returns its outcome.

    Must be called from the main thread. `screen` gets the launch's output (default stdout),
    `stream` the unittest report (default stderr); `log_dir` the launch's log files.

    Raises:
        LaunchError: the test file's launch cannot run (one line naming file and line).
    """
    from zros.testing.domains import isolated_domain
    with isolated_domain():
        return _Run(test, dict(launch_arguments or {}), log_dir, screen, stream or sys.stderr, debug).run()
