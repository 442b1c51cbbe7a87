"""nav2_lifecycle_manager's lifecycle_manager: brings a list of lifecycle nodes up and down in
order, and watches them while they run.

    zros run nav2_lifecycle_manager lifecycle_manager --ros-args -r __node:=lifecycle_manager_navigation \\
        -p node_names:="['map_server', 'amcl']" -p autostart:=true

Parameters (Nav2's): `node_names` (configured then activated in this order, brought down in
reverse), `autostart` (start up at once), `bond_timeout` (0 turns the health check off),
`attempt_respawn_reconnection` and `bond_respawn_max_duration` (after a crash, start the stack
up again when every node answers once more, if that happens within this many seconds),
`service_timeout` (seconds to wait for a node's lifecycle services and for its `get_state`
answer, as in Nav2 after Jazzy: a busy machine answers late, and a late answer is not a
failed node; the transition itself is waited for as long as its callback runs). A `get_state`
that does not answer in time is asked again, up to `_STATE_ATTEMPTS` times in all, while the
node is still in the graph: on a machine with every core busy one late answer is not yet a
failed transition.
Services: `<manager>/manage_nodes` (nav2_msgs/srv/ManageLifecycleNodes: STARTUP, PAUSE,
RESUME, RESET, SHUTDOWN) and `<manager>/is_active` (std_srvs/srv/Trigger).

The health check replaces Nav2's bond heartbeats with the nodes' liveliness tokens: a managed
node whose process dies is noticed within `_DOWN_CONFIRM_S`, not after `bond_timeout`. Then, as
in Nav2, it is reported and the rest of the stack is reset (deactivated and cleaned up).

A stop on purpose is not a failure. Ctrl-C on a launch signals every node at once, so managed
nodes may vanish an instant before the manager's own signal lands: a node must stay gone for
`_DOWN_CONFIRM_S` before it counts as down, and once the manager is stopping (a signal, or its
context shut down) it neither reports nodes down nor logs failed transitions, as Nav2's
manager drops its bonds in its pre-shutdown callback.
"""
from __future__ import annotations

import sys
import threading
import time
from typing import Any, Callable

import zros
from zros.callback_groups import MutuallyExclusiveCallbackGroup, ReentrantCallbackGroup
from zros.clock import Clock, ClockType
from zros.errors import ServiceCallError
from zros.executors import ExternalShutdownException, spin_nodes
from zros.graph import EntityKind
from zros.lifecycle import LifecycleClient
from zros.node import Node
from zros.signals import signal_received

from interfaces.lifecycle_msgs.msg import Transition
from interfaces.nav2_msgs.srv import ManageLifecycleNodes
from interfaces.std_srvs.srv import Trigger

_VERB = {Transition.TRANSITION_CONFIGURE: 'Configuring', Transition.TRANSITION_CLEANUP: 'Cleaning up',
         Transition.TRANSITION_ACTIVATE: 'Activating', Transition.TRANSITION_DEACTIVATE: 'Deactivating',
         Transition.TRANSITION_UNCONFIGURED_SHUTDOWN: 'Shutting down'}
_GOAL = {Transition.TRANSITION_CONFIGURE: 'inactive', Transition.TRANSITION_CLEANUP: 'unconfigured',
         Transition.TRANSITION_ACTIVATE: 'active', Transition.TRANSITION_DEACTIVATE: 'inactive',
         Transition.TRANSITION_UNCONFIGURED_SHUTDOWN: 'finalized'}
_FORWARD = (Transition.TRANSITION_CONFIGURE, Transition.TRANSITION_ACTIVATE)
_WAIT_LOG_PERIOD_S = 2.0
_HEALTH_PERIOD_S = 0.2
_RESPAWN_PERIOD_S = 1.0
# How long a managed node must stay out of the graph before it counts as down [s]: long enough
# for this manager's own signal to land when a launch stops everything at once.
_DOWN_CONFIRM_S = 1.0
# How many times a transition's get_state is asked (each within service_timeout) before it fails.
_STATE_ATTEMPTS = 3


class LifecycleManager(Node):
    def __init__(self) -> None:
        super().__init__('lifecycle_manager')
        self.declare_parameter('node_names', [''])
        self.declare_parameter('autostart', False)
        self.declare_parameter('bond_timeout', 4.0)
        self.declare_parameter('bond_respawn_max_duration', 10.0)
        self.declare_parameter('attempt_respawn_reconnection', True)
        self.declare_parameter('service_timeout', 5.0)
        self.declare_parameter('bond_heartbeat_period', 0.25)   # Nav2's; liveliness needs no heartbeat
        self.node_names = [n for n in self.get_parameter('node_names').value if n]
        self._lifecycle = {name: LifecycleClient(self, name) for name in self.node_names}
        self._fqn = {name: self.resolve_topic_name(name) for name in self.node_names}
        self._busy = threading.Lock()
        self.system_active = False
        self._respawn_started: float | None = None
        self._missing_since: dict[str, float] = {}
        self._wall = Clock(clock_type=ClockType.STEADY_TIME)
        work = MutuallyExclusiveCallbackGroup()
        self.create_service(ManageLifecycleNodes, '~/manage_nodes', self._on_manage_nodes, callback_group=work)
        self.create_service(Trigger, '~/is_active', self._on_is_active, callback_group=ReentrantCallbackGroup())
        self._health = self.create_timer(_HEALTH_PERIOD_S, self._check_health, work, clock=self._wall, autostart=False)
        self._respawn = self.create_timer(_RESPAWN_PERIOD_S, self._check_respawn, work, clock=self._wall,
                                          autostart=False)
        self.get_logger().info(f"Managing {', '.join(self.node_names) or 'no nodes (node_names is empty)'}")
        if self.get_parameter('autostart').value:
            self._autostart = self.create_timer(0.01, self._start_once, work, clock=self._wall)

    def _message(self, text: str) -> None:
        self.get_logger().info(text)

    def _service_timeout(self) -> float:
        return float(self.get_parameter('service_timeout').value)

    def _stopping(self) -> bool:
        """Whether this manager is being stopped (Ctrl-C, SIGTERM, its context shut down)."""
        return signal_received() or not self.context.ok()

    def _failure(self, text: str) -> None:
        """Log a failed step as an error, unless the manager is stopping: then the nodes going
        away under it is expected, and the step is logged at DEBUG only."""
        if self._stopping():
            self.get_logger().debug(f'{text} (stopping)')
        else:
            self.get_logger().error(text)

    # -- transitions ------------------------------------------------------------------------------
    def _wait_for(self, name: str) -> bool:
        """Wait (logging now and then) until `name`'s lifecycle services exist; False on shutdown."""
        client = self._lifecycle[name]
        while self.context.ok():
            if client.wait_for_services(timeout_sec=_WAIT_LOG_PERIOD_S):
                return True
            self._message(f'Waiting for service {name}/get_state...')
        return False

    def _change_state(self, name: str, transition: int, wait: bool) -> bool:
        self._message(f'{_VERB[transition]} {name}')
        client = self._lifecycle[name]
        try:
            if wait and not self._wait_for(name):
                return False
            if client.change_state(transition) and self._state_after(name) == _GOAL[transition]:
                return True
        except ServiceCallError as exc:
            self._failure(f'Failed to change state for node: {name}. Exception: {exc}.')
            return False
        self._failure(f'Failed to change state for node: {name}')
        return False

    def _state_after(self, name: str) -> str:
        """`name`'s state label after a transition: asked again when the answer is late and the
        node is still alive (a busy machine), raising ServiceCallError after _STATE_ATTEMPTS."""
        timeout = self._service_timeout()
        attempt = 1
        while True:
            try:
                return self._lifecycle[name].get_state(timeout_sec=timeout).label
            except ServiceCallError:
                if attempt >= _STATE_ATTEMPTS or self._stopping() or self._fqn[name] not in self._alive():
                    raise
            attempt += 1
            self.get_logger().warn(f'{name}/get_state did not answer within {timeout:g} s (service_timeout); '
                                   f'asking again ({attempt} of {_STATE_ATTEMPTS})')

    def _change_all(self, transition: int, *, hard: bool = False, wait: bool = False) -> bool:
        """Configure/activate in list order, the rest in reverse; stop at the first failure
        unless `hard` (then carry on and report the overall outcome)."""
        names = self.node_names if transition in _FORWARD else list(reversed(self.node_names))
        ok = True
        for name in names:
            if not self._change_state(name, transition, wait):
                ok = False
                if not hard:
                    return False
        return ok

    def startup(self) -> bool:
        self._message('Starting managed nodes bringup...')
        if not (self._change_all(Transition.TRANSITION_CONFIGURE, wait=True)
                and self._change_all(Transition.TRANSITION_ACTIVATE)):
            self._failure('Failed to bring up all requested nodes. Aborting bringup.')
            return False
        self._message('Managed nodes are active')
        self._set_active(True)
        return True

    def shutdown(self) -> bool:
        self._set_active(False)
        self._message('Shutting down managed nodes...')
        self._message('Deactivate, cleanup, and shutdown nodes')
        for transition in (Transition.TRANSITION_DEACTIVATE, Transition.TRANSITION_CLEANUP,
                           Transition.TRANSITION_UNCONFIGURED_SHUTDOWN):
            self._change_all(transition, hard=True)  # Nav2 stops at a failure; every node should go down
        self._message('Managed nodes have been shut down')
        return True

    def reset(self, hard: bool = False) -> bool:
        self._set_active(False)
        self._message('Resetting managed nodes...')
        ok = self._change_all(Transition.TRANSITION_DEACTIVATE, hard=hard)
        if ok or hard:
            ok = self._change_all(Transition.TRANSITION_CLEANUP, hard=hard) and ok
        if not ok and not hard:
            self._failure('Failed to reset nodes: aborting reset')
            return False
        self._message('Managed nodes have been reset')
        return True

    def pause(self) -> bool:
        self._set_active(False)
        self._message('Pausing managed nodes...')
        if not self._change_all(Transition.TRANSITION_DEACTIVATE):
            self._failure('Failed to pause nodes: aborting pause')
            return False
        self._message('Managed nodes have been paused')
        return True

    def resume(self) -> bool:
        self._message('Resuming managed nodes...')
        if not self._change_all(Transition.TRANSITION_ACTIVATE):
            self._failure('Failed to resume nodes: aborting resume')
            return False
        self._message('Managed nodes are active')
        self._set_active(True)
        return True

    def _set_active(self, active: bool) -> None:
        self.system_active = active
        self._missing_since.clear()
        if active and self.get_parameter('bond_timeout').value > 0:
            self._health.reset()
        else:
            self._health.cancel()

    def _exclusively(self, action: Callable[[], bool]) -> bool:
        with self._busy:
            return action()

    # -- callbacks ----------------------------------------------------------------------------------
    def _start_once(self) -> None:
        self._autostart.cancel()
        self._exclusively(self.startup)

    def _on_manage_nodes(self, request: Any, response: Any) -> Any:
        actions = {ManageLifecycleNodes.Request.STARTUP: self.startup,
                   ManageLifecycleNodes.Request.PAUSE: self.pause,
                   ManageLifecycleNodes.Request.RESUME: self.resume,
                   ManageLifecycleNodes.Request.RESET: self.reset,
                   ManageLifecycleNodes.Request.SHUTDOWN: self.shutdown}
        action = actions.get(request.command)
        if action is None:
            self.get_logger().error(f'manage_nodes: unknown command {request.command} (0-4: STARTUP, PAUSE, RESUME, '
                                    'RESET, SHUTDOWN)')
            response.success = False
        else:
            response.success = self._exclusively(action)
        return response

    def _on_is_active(self, request: Any, response: Any) -> Any:
        response.success = self.system_active
        return response

    def _alive(self) -> set[str]:
        return {e.node_fqn for e in self.context.graph.entities() if e.kind == EntityKind.NODE}

    def _check_health(self) -> None:
        if not self.system_active or self._stopping():
            return
        alive = self._alive()
        now = time.monotonic()
        for name in self.node_names:
            if self._fqn[name] in alive:
                self._missing_since.pop(name, None)
                continue
            if now - self._missing_since.setdefault(name, now) < _DOWN_CONFIRM_S or self._stopping():
                continue
            self._missing_since.clear()
            self._message(f'Have not received a heartbeat from {name}.')
            self.get_logger().error(f'CRITICAL FAILURE: SERVER {name} IS DOWN (its process is gone). '
                                    'Shutting down related nodes.')
            self._exclusively(lambda: self.reset(hard=True))
            if self.get_parameter('attempt_respawn_reconnection').value:
                self._respawn_started = time.monotonic()
                self._respawn.reset()
            return

    def _check_respawn(self) -> None:
        if self.system_active or self._respawn_started is None:
            self._respawn.cancel()
            return
        try:
            for client in self._lifecycle.values():
                client.get_state(timeout_sec=self._service_timeout())
        except ServiceCallError:
            if time.monotonic() - self._respawn_started >= self.get_parameter('bond_respawn_max_duration').value:
                self._message('Failed to re-establish connection from a server crash after maximum timeout.')
                self._respawn_started = None
                self._respawn.cancel()
            return
        self._message('Successfully re-established connections from server respawns, starting back up.')
        self._respawn_started = None
        self._respawn.cancel()
        self._exclusively(self.startup)


def main(args: list[str] | None = None) -> int:
    try:
        with zros.init(args=args):
            spin_nodes(LifecycleManager(), num_threads=2)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    return 0


if __name__ == '__main__':
    sys.exit(main())
