"""`LaunchService` (launch.LaunchService): run launch descriptions through an event queue, as
code written against launch's classes expects (`include_launch_description`, `emit_event`,
`run`, `shutdown`).

It is `zros launch`'s runtime with launch's event loop in front: the service's context
(zros.launch.context, with its event queue) visits what handlers return with the same walk
`resolve()` uses, and hands the effects (processes, log lines, timers, shutdowns) to the
Supervisor (zros.launch.supervisor), which runs them exactly as under `zros launch`. The
supervisor reports its processes back as launch.events.process events, and drains the queue on
its own thread between the things it watches.
"""
from __future__ import annotations

import contextlib
import queue
import sys
import threading
from pathlib import Path
from typing import Any, Coroutine, Iterator

from zros.launch.action import report_completion
from zros.launch.context import LaunchContext
from zros.launch.description import walk
from zros.launch.errors import LaunchError
from zros.launch.event_handlers.on_include_launch_description import OnIncludeLaunchDescription
from zros.launch.events.include_launch_description import IncludeLaunchDescription
from zros.launch.events.process import ProcessExited, ProcessIO, ProcessStarted
from zros.launch.events.shutdown import Shutdown
from zros.launch.plan import Plan, ProcessSpec
from zros.launch.supervisor import ProcessObserver, Supervisor

__all__ = ['LaunchService']

try:
    # launch runs on osrf_pycommon's asyncio loop and so loads `osrf_pycommon.process_utils`;
    # code written against launch (its own tests) reaches that module through the package
    # once launch is imported. zros needs no part of it: loaded only when it is installed.
    import osrf_pycommon.process_utils  # noqa: F401
except ImportError:
    pass


class LaunchService(ProcessObserver):
    """One launch: a context, its event queue, and (while `run()` runs) a supervisor.

    Args:
        argv: arguments for the launch description (`context.argv`).
        noninteractive: the launch runs without a terminal (`context.noninteractive`).
        debug: DEBUG messages too (command lines, environment, signals).

    `run()`, or `run_async()` on the main thread's asyncio loop, must be called from the main
    thread (the supervisor forks and handles signals); `emit_event`,
    `include_launch_description` and `shutdown` may be called from any thread.
    """

    def __init__(self, *, argv: list[str] | None = None, noninteractive: bool = False, debug: bool = False,
                 context: LaunchContext | None = None) -> None:
        self.__context = context if context is not None else LaunchContext()
        self.__context.argv = list(argv or [])
        self.__context.noninteractive = noninteractive
        self.debug = debug
        self._supervisor: Supervisor | None = None
        self._shutdown_when_idle: bool | None = True
        self._shutting_down = False
        self._announcing = False      # the supervisor is stopping for a Shutdown event being dispatched
        self._running: dict[str, tuple[int, list[str]]] = {}   # process name -> (pid, argv)
        self._loop_thread: threading.Thread | None = None   # the thread of run_async()'s loop
        # The launch's own handler, registered after those already on the context (a resolved
        # file's) so that users' handlers see events first.
        self.__context.register_event_handler(OnIncludeLaunchDescription(), append=True)

    @property
    def context(self) -> LaunchContext:
        return self.__context

    # -- from any thread -------------------------------------------------------------------------
    def emit_event(self, event: Any) -> None:
        """Queue `event`; its handlers run on the launch's thread (now, if it is running)."""
        self.__context.emit_event_sync(event)

    def include_launch_description(self, launch_description: Any) -> None:
        """Visit `launch_description` in this launch (queued as an IncludeLaunchDescription event)."""
        self.emit_event(IncludeLaunchDescription(launch_description))

    def shutdown(self, force_sync: bool = False) -> Coroutine[Any, Any, None] | None:
        """End the launch: a Shutdown event, which its handlers see before the processes stop.

        launch's contract: on the thread whose asyncio loop runs `run_async()`, it returns a
        coroutine that queues the event when awaited (`loop.create_task(ls.shutdown())`), unless
        `force_sync`; from any other thread, or under `run()`, the event is queued now and it
        returns None. A launch that is not running is left alone (None).
        """
        if self._supervisor is None:
            return None
        event = Shutdown(reason='LaunchService.shutdown() called')
        if not force_sync and self._loop_thread is threading.current_thread():
            return self.__context.emit_event(event)
        self.emit_event(event)
        return None

    # -- running -----------------------------------------------------------------------------------
    def run(self, *, shutdown_when_idle: bool = True) -> int:
        """Run until shut down, or (with `shutdown_when_idle`) until nothing is left to do, then
        a Shutdown event; 0, or 1 when a process could not be started or an action failed
        (a LaunchError, logged)."""
        supervisor = self._supervisor_for(shutdown_when_idle)
        try:
            with self._supervising(supervisor):
                return supervisor.run()
        except LaunchError as exc:
            return _failed(exc)

    async def run_async(self, *, shutdown_when_idle: bool = True) -> int:
        """`run()` as a coroutine of the main thread's asyncio loop, as launch's users drive it:
        `task = loop.create_task(ls.run_async())`, other work on the loop, then
        `loop.create_task(ls.shutdown())` and `loop.run_until_complete(task)`. The supervisor
        runs on the loop's thread and awaits between its passes, so the loop keeps running;
        `context.asyncio_loop` is the loop meanwhile."""
        import asyncio
        supervisor = self._supervisor_for(shutdown_when_idle)
        self.__context._set_asyncio_loop(asyncio.get_running_loop())
        self._loop_thread = threading.current_thread()
        try:
            with self._supervising(supervisor):
                return await supervisor.run_async()
        except LaunchError as exc:
            return _failed(exc)
        finally:
            self._loop_thread = None
            self.__context._set_asyncio_loop(None)

    @classmethod
    def run_plan(cls, plan: Plan, *, log_dir: Path | None, debug: bool = False) -> int:
        """What `zros launch` runs: a resolved plan, in the context it was resolved in (so the
        handlers the file registered see its events). It ends when nothing is left to do,
        without a Shutdown event, as `zros launch` always has."""
        service = cls(debug=debug, context=plan.context)
        service._shutdown_when_idle = None
        supervisor = Supervisor(plan, log_dir=log_dir, debug=debug, observer=service)
        with service._supervising(supervisor):
            return supervisor.run()

    def _supervisor_for(self, shutdown_when_idle: bool) -> Supervisor:
        """The supervisor of a run from code: no plan of its own (the queued events bring the
        actions), no log directory and no discovery hub."""
        self._shutdown_when_idle = shutdown_when_idle
        return Supervisor(Plan('<LaunchService>'), log_dir=None, debug=self.debug, hub=False,
                          observer=self, keep_alive=not shutdown_when_idle)

    @contextlib.contextmanager
    def _supervising(self, supervisor: Supervisor) -> Iterator[None]:
        """While `supervisor` runs, events emitted from any thread wake it to drain the queue."""
        self._shutting_down = False
        self._supervisor = supervisor
        self.__context._wakeup = supervisor.wake
        try:
            yield
        finally:
            self.__context._wakeup = lambda: None
            self._supervisor = None

    # -- the supervisor's thread (ProcessObserver) ---------------------------------------------
    def pump(self) -> None:
        """Offer each queued event to the handlers, newest handler first; visit what they return."""
        while True:
            try:
                event = self.__context._event_queue.get_nowait()
            except queue.Empty:
                return
            self._dispatch(event)

    def idle(self) -> bool:
        if not self.__context._event_queue.empty():
            return True
        if self._shutdown_when_idle and not self._shutting_down:
            self.emit_event(Shutdown(reason='idle'))
            return True
        return False

    def shutting_down(self, reason: str) -> None:
        """A shutdown the supervisor began itself (Ctrl-C, a Shutdown action, a process's
        on_exit) or was asked for again while stopping: the context's handlers see it as a
        Shutdown event, before the processes stop. Not for the one a Shutdown event began (the
        handlers have seen that event)."""
        if not self._announcing:
            self._dispatch(Shutdown(reason=reason, due_to_sigint='SIGINT' in reason))

    def started(self, name: str, spec: ProcessSpec, pid: int, cmd: list[str]) -> None:
        self._running[name] = (pid, list(cmd))
        self.emit_event(ProcessStarted(action=spec.source, name=name, cmd=cmd, cwd=spec.cwd, env=None, pid=pid))

    def output(self, name: str, spec: ProcessSpec, is_stderr: bool, lines: list[str]) -> None:
        """ProcessIO events, only while an OnProcessIO handler listens: a launch's output is
        its busiest path, and an event per chunk would cost it for nothing."""
        from zros.launch.event_handlers.on_process_io import OnProcessIO
        if not any(isinstance(handler, OnProcessIO) for handler in self.__context.event_handlers):
            return
        text = ('\n'.join(lines) + '\n').encode()
        pid, cmd = self._running.get(name, (0, []))
        self.emit_event(ProcessIO(action=spec.source, name=name, cmd=cmd, cwd=spec.cwd, env=None, pid=pid,
                                  text=text, fd=2 if is_stderr else 1))

    def exited(self, name: str, spec: ProcessSpec, pid: int, returncode: int, cmd: list[str]) -> None:
        self.emit_event(ProcessExited(action=spec.source, name=name, cmd=cmd, cwd=spec.cwd, env=None, pid=pid,
                                      returncode=returncode))
        if getattr(spec.source, 'completes_on_exit', False):
            report_completion(spec.source, self.__context)

    def _dispatch(self, event: Any) -> None:
        context = self.__context
        for handler in context.event_handlers:
            if not handler.matches(event):
                continue
            context._push_locals()
            try:
                entities = handler.handle(event, context)
                self._visit(entities)
            finally:
                context._pop_locals()
        if isinstance(event, Shutdown):
            self._shutting_down = True
            if self._supervisor is not None:
                # launch's rule: in an interactive launch, a Shutdown due to SIGINT means the
                # terminal's Ctrl-C already reached the processes; only escalation is left
                delivered = bool(getattr(event, 'due_to_sigint', False)) and not context.noninteractive
                self._announcing = True
                try:
                    self._supervisor.shutdown(str(event.reason or 'Shutdown event'), sigint_delivered=delivered)
                finally:
                    self._announcing = False

    def _visit(self, entities: Any) -> None:
        """Resolve `entities` in the context and carry out their effects."""
        from zros.launch.actions.group import check_actions
        from zros.launch.origin import origin_here
        actions = check_actions(entities, origin_here('LaunchService'))
        if not actions:
            return
        context = self.__context
        context.begin_capture()
        try:
            walk(actions, context)
        except LaunchError as exc:
            if self._supervisor is None:
                raise
            # as launch: the error is logged and the launch ends with exit code 1
            self._supervisor.fail('launch', f'Caught exception in launch: {exc}')
            return
        finally:
            effects = context.end_capture()
        if self._supervisor is not None:
            self._supervisor.carry_out(effects)


def _failed(exc: LaunchError) -> int:
    """launch's contract: a launch that fails (a node whose package is missing, ...) is a return
    code, with the reason logged; the supervisor has stopped its processes."""
    print(f'[ERROR] [launch]: {exc}', file=sys.stderr, flush=True)
    return 1
