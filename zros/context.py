"""The process's connection to the zros system: one Zenoh session, shared by all its nodes.

`zros.init()` opens it (becoming the loopback hub if none is running, see zros.config), and
`zros.shutdown()` closes everything in order: executors stop, nodes undeclare their entities
and liveliness tokens, then the session closes. An atexit hook does the same for programs that
forget, because a Zenoh session left open can keep the interpreter from exiting.

Once SIGINT or SIGTERM has come in, the process is ending, and what it destroys is withdrawn
from the network by the session's close rather than declaration by declaration: each undeclare
is a message to every peer, and when a whole launch stops, each node sending its 20 or so to
every other one was half of the stop's CPU (50 nodes); a close withdraws everything with one
message per link. (A program that goes on after Ctrl-C keeps what it destroyed declared until
it shuts zros down.)
"""
from __future__ import annotations

import atexit
import itertools
import os
import sys
import threading
import weakref
from typing import Any, Callable

from zros.allocator import tune as tune_allocator
from zros.arguments import RosArgs, parse_ros_args
from zros.config import SessionSettings, open_session, settings_from_env
from zros.errors import NotInitializedError
from zros.handle import Handle
from zros.logging import set_logger_level, severity_from_string

__all__ = ['Context', 'get_default_context', 'initialized_contexts', 'exit_process']

# How long a shutdown waits for the callback an executor is running to return before it
# destroys the nodes under it (a callback that blocks longer sees its entities go).
_CALLBACK_GRACE_S = 1.0
# How long a shutdown that follows SIGINT/SIGTERM waits for the Zenoh session to close.
_SIGNAL_CLOSE_S = 0.2


class Context:
    def __init__(self) -> None:
        self._lock = threading.RLock()
        self._session = None
        self._is_hub = False
        self._settings: SessionSettings | None = None
        self._graph = None
        self._graph_service = None
        self._stats_service = None
        self._args = RosArgs()
        self._argv: list[str] = []
        self._ok = False
        self._provisional = False      # opened on the program's behalf; its own init() replaces it
        self._stop_requested = False   # a signal came in; the shutdown is on its way
        self._ids = itertools.count(1)
        self._nodes: weakref.WeakSet = weakref.WeakSet()
        self._executors: weakref.WeakSet = weakref.WeakSet()
        self._on_shutdown: list[Callable[[], None]] = []
        self._closed = threading.Event()
        self._closed.set()
        self._withdrawn: list = []   # declarations the session's close withdraws (see the module doc)
        self._handle: Handle | None = None

    # -- life cycle ----------------------------------------------------------------------
    def init(self, args: list[str] | None = None, *, domain_id: int | None = None,
             install_signal_handlers: Any = True, mesh: bool = True,
             connect_wait: float | None = None, provisional: bool = False) -> 'Context':
        """Open the session.

        Args:
            install_signal_handlers: a zros.signals.SignalHandlerOptions, or True (both
                signals) / False (none); see zros.signals.
            mesh: False links only to the hub or router (for tools that only read the graph).
            connect_wait: how long a client-mode session waits for its router (None: forever).
            provisional: opened on the program's behalf (launch tests run with zros initialized,
                since tests written for ROS create nodes without `rclpy.init()`); the program's
                own `init()` then shuts this one down and opens the context its way, where an
                init of an initialized context raises.
        """
        if self._ok and self._provisional:
            self.shutdown()
        with self._lock:
            if self._ok:
                raise RuntimeError('Context.init() must only be called once')
            self._provisional = provisional
            argv = list(sys.argv if args is None else args)
            for arg in argv:
                # Arguments travel as UTF-8 (to nodes, launch files and the graph); an undecodable
                # one (PEP 383 surrogates from a wrong locale) fails here, as in rclpy.
                arg.encode('utf-8')
            parsed = parse_ros_args(argv)
            for logger, level in parsed.log_levels:
                set_logger_level(logger, severity_from_string(level))
            settings = settings_from_env(domain_id=domain_id, enclave=parsed.enclave)
            tune_allocator()
            self._session, self._is_hub = open_session(settings, mesh=mesh, connect_wait=connect_wait)
            self._settings, self._args, self._argv = settings, parsed, argv
            self._graph = None
            self._handle = Handle('context')
            self._closed.clear()
            self._ok = True
            self._stop_requested = False
            if self._is_hub:
                from zros.graph import GraphService
                self.graph.start()
                self._graph_service = GraphService(self._session, settings.domain_id, self.graph)
            from zros.graph import StatsService
            self._stats_service = StatsService(self._session, settings.domain_id, str(self._session.info.zid()),
                                               self._subscriptions)
        _register_exit_hook(self)
        from zros.signals import SignalHandlerOptions, install_signal_handlers as install
        if install_signal_handlers is True:
            install_signal_handlers = SignalHandlerOptions.ALL
        install(SignalHandlerOptions(install_signal_handlers or SignalHandlerOptions.NO))
        return self

    def ok(self) -> bool:
        return self._ok and not self._stop_requested

    def _request_stop(self) -> None:
        """A signal arrived: `ok()` is False from now on, and executors stop waiting (the
        shutdown itself runs on the signal watcher's thread)."""
        self._stop_requested = True
        for executor in list(self._executors):
            executor.wake()

    def shutdown(self) -> None:
        """Close everything this context opened. Calling it twice is harmless; a call made
        while another thread is shutting down waits for it (up to 5 s), so the interpreter
        never exits in the middle of closing the Zenoh session."""
        with self._lock:
            waiting = not self._ok
            if not waiting:
                self._ok = False
                callbacks, self._on_shutdown = self._on_shutdown, []
        if waiting:
            self._closed.wait(5.0)
            return
        executors = list(self._executors)
        for executor in executors:
            executor.wake()
        for executor in executors:
            executor._wait_until_idle(_CALLBACK_GRACE_S)
        for callback in callbacks:
            try:
                callback()
            except Exception as exc:  # noqa: BLE001 - one failing hook must not stop the rest
                print(f'zros: shutdown callback failed: {exc}', file=sys.stderr)
        with self._lock:
            # First stop following the graph: when a whole launch stops, every process would
            # otherwise run a Python callback for each token of every other one as they go.
            if self._graph is not None:
                self._graph.close(self._undeclare)
                self._graph = None
        for node in list(self._nodes):
            node.destroy_node()
        with self._lock:
            if self._stats_service is not None:
                self._stats_service.close(self._undeclare)
                self._stats_service = None
            if self._graph_service is not None:
                self._graph_service.close(self._undeclare)
                self._graph_service = None
            opened, self._session = [self._session], None
            withdrawn, self._withdrawn = self._withdrawn, []
        if opened[0] is not None:
            _close_session(opened, withdrawn)
        self._closed.set()

    def _undeclare(self, declaration: Any) -> None:
        """Undeclare a Zenoh declaration of this context's session (a token, publisher,
        subscriber or queryable); after a signal, leave it to the session's close."""
        from zros.signals import signal_received
        with self._lock:
            if signal_received() and self._session is not None:
                self._withdrawn.append(declaration)
                return
        from zros.graph import undeclare_quietly
        undeclare_quietly(declaration)

    def try_shutdown(self) -> None:
        self.shutdown()

    def on_shutdown(self, callback: Callable[[], None]) -> None:
        with self._lock:
            self._on_shutdown.append(callback)

    def destroy(self) -> None:
        """Release the context (rclpy's Context.destroy): zros holds nothing beyond what
        `shutdown()` closes, so this shuts it down if it is still up, once no `with
        context.handle:` block holds it. Its handle is invalid from now on."""
        if self._handle is None:
            self.shutdown()
        else:
            self._handle.destroy_when_not_in_use(self.shutdown)

    @property
    def handle(self) -> Handle | None:
        """rclpy's opaque handle of the context (zros.handle): None until the first `init()`,
        valid until `destroy()`; it stands for the context's Zenoh session."""
        return self._handle

    def __enter__(self) -> 'Context':
        """`with Context() as ctx:` initializes it (with default arguments) unless it is
        initialized already, and shuts it down at the end of the block, as rclpy."""
        if not self._ok:
            self.init()
        return self

    def __exit__(self, *exc: object) -> None:
        self.shutdown()

    # -- what nodes use ------------------------------------------------------------------
    @property
    def session(self) -> Any:
        if self._session is None:
            raise NotInitializedError('zros is not initialized: call zros.init() first')
        return self._session

    @property
    def settings(self) -> SessionSettings:
        if self._settings is None:
            raise NotInitializedError('zros is not initialized: call zros.init() first')
        return self._settings

    @property
    def domain_id(self) -> int:
        return self.settings.domain_id

    def get_domain_id(self) -> int:
        """The ROS domain id this context's session was opened for (rclpy's Context.get_domain_id)."""
        return self.domain_id

    def check_can_shut_down(self) -> None:
        """rclpy.shutdown()'s precondition: the context is initialized, or a signal has shut it down
        (the program's own shutdown that follows is expected and harmless).

        Raises:
            RuntimeError: The context was never initialized, or was shut down already.
        """
        with self._lock:
            if not self._ok and not self._stop_requested:
                raise RuntimeError('Context must be initialized before it can be shut down '
                                   '(use try_shutdown() to shut it down only if it is up)')

    @property
    def is_hub(self) -> bool:
        return self._is_hub

    @property
    def hub_wait(self) -> float | None:
        """How long a graph read waits for a hub's answer: the loopback hub is always there; with
        explicit endpoints the router may be a plain Zenoh router that never answers."""
        return None if self.settings.uses_hub else 0.3

    @property
    def ros_args(self) -> RosArgs:
        return self._args

    @property
    def argv(self) -> list[str]:
        return list(self._argv)

    @property
    def graph(self):
        from zros.graph import Graph
        with self._lock:
            if self._graph is None:
                self._graph = Graph(self.session, self.domain_id, is_hub=self._is_hub, hub_wait=self.hub_wait)
            return self._graph

    def _subscriptions(self) -> list:
        return [sub for node in list(self._nodes) for sub in node.subscriptions]

    def next_id(self) -> int:
        return next(self._ids)

    def _register_node(self, node: Any) -> None:
        if not self._ok:
            raise NotInitializedError('zros is not initialized: call zros.init() first')
        self._nodes.add(node)

    def _unregister_node(self, node: Any) -> None:
        self._nodes.discard(node)

    def _register_executor(self, executor: Any) -> None:
        self._executors.add(executor)

    def _unregister_executor(self, executor: Any) -> None:
        self._executors.discard(executor)


_default_context = Context()
_CLOSER_NAME = 'zros-close'
# The names of the subscriptions' pump threads (zros.subscription) begin with this: like Zenoh's
# callback threads they end once the session is closed.
PUMP_THREAD_PREFIX = 'zros-sub '
_exit_hooked: weakref.WeakSet = weakref.WeakSet()


def get_default_context() -> Context:
    return _default_context


def _close_session(opened: list, withdrawn: list) -> None:
    """Close the Zenoh session in `opened` (its only reference), which withdraws the declarations
    in `withdrawn` (kept alive until then). Zenoh closes its links one after the other, so with
    100 peers a close takes a second or more; after a signal the process is about to end, and
    the close is given `_SIGNAL_CLOSE_S`: what is left is ended with the process, which peers
    see as the links closing, and they drop all that the process had declared.

    The thread that closes the session also drops it, and after a signal that is a thread the
    interpreter waits for: freeing a session blocks in Zenoh without the GIL, and a thread that
    comes back for the GIL once the interpreter is finalizing aborts the whole process."""
    from zros.signals import signal_received

    def close() -> None:
        session = opened.pop()
        try:
            session.close()
        except Exception:  # noqa: BLE001 - the session may already be closing at exit
            pass
        withdrawn.clear()
        del session
    if not signal_received():
        close()
        return
    closer = threading.Thread(target=close, name=_CLOSER_NAME)
    closer.start()
    closer.join(_SIGNAL_CLOSE_S)


def initialized_contexts() -> list[Context]:
    """Every context of this process that is initialized now (what a signal shuts down)."""
    return [context for context in list(_exit_hooked) if context._ok]


def _register_exit_hook(context: Context) -> None:
    """Shut the context down when the program ends without calling zros.shutdown().

    Zenoh's callback threads are not daemon threads, and Python joins those *before* it runs
    atexit handlers, so an atexit hook alone never runs and the process hangs at exit. The
    threading module's own exit hook runs before that join (concurrent.futures uses it too).
    """
    if context in _exit_hooked:
        return
    _exit_hooked.add(context)
    register = getattr(threading, '_register_atexit', None)
    try:
        if register is None:
            raise RuntimeError
        register(context.shutdown)
    except RuntimeError:  # no threading hook, or the interpreter is already shutting down
        atexit.register(context.shutdown)


def exit_process(code: int) -> None:
    """End a zros command (`zros run` nodes and CLI verbs) once its work is done.

    Everything zros opened is shut down here (the Zenoh sessions closed, so nothing sent is
    lost), then atexit functions run and the process exits without the interpreter's
    finalization. That skips Zenoh's runtime teardown, which waits up to a second per runtime
    for tasks of links that are already closed: a 50-node launch would otherwise spend most of
    its stop there. A program that left threads of its own running exits the normal way.
    """
    for context in initialized_contexts():
        context.shutdown()
    main = threading.main_thread()
    own = [t for t in threading.enumerate() if t is not main and not t.daemon and t.is_alive()
           and not t.name.endswith('(pyo3-closure)')    # Zenoh's callback threads, done once closed
           and not t.name.startswith(PUMP_THREAD_PREFIX)   # the subscriptions' pumps, the same
           and t.name != _CLOSER_NAME]                  # exiting ends the close (see _close_session)
    if own:
        sys.exit(code)
    atexit._run_exitfuncs()
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except Exception:  # noqa: BLE001 - a closed or broken stream must not stop the exit
            pass
    os._exit(code)
