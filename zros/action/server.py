"""Action servers (rclpy.action.ActionServer's interface) on zros services and topics.

Goals are accepted by default and cancels rejected by default, as in rclpy. The goal's
execute callback runs as an executor task outside any callback group (as rclpy does), so
with a MultiThreadedExecutor several goals run at once while new goals and cancel requests
are still answered. Results stay available for `result_timeout` seconds after a goal ends;
a get-result request for a running goal is answered when the goal ends, however long it runs.
"""
from __future__ import annotations

import enum
import inspect
import threading
import time
import uuid
from collections import deque
from typing import TYPE_CHECKING, Any, Callable

from zros.action.counts import NumberOfEntities
from zros.action_types import protocol_types
from zros.graph import EntityKind
from zros.message import packed_array, serialize_parts
from zros.publisher import Publisher
from zros.qos import QoSProfile, qos_profile_action_status_default, qos_profile_services_default
from zros.service import DeferredResponse

if TYPE_CHECKING:
    from zros.node import Node
    from zros.service import Service

__all__ = ['ActionServer', 'ServerGoalHandle', 'GoalResponse', 'CancelResponse', 'GoalStatus',
           'default_goal_callback', 'default_cancel_callback', 'default_handle_accepted_callback']


class GoalResponse(enum.IntEnum):
    """What a goal callback answers: reject the goal, or accept it."""
    REJECT = 1
    ACCEPT = 2


class CancelResponse(enum.IntEnum):
    """What a cancel callback answers: reject the cancel request, or accept it."""
    REJECT = 1
    ACCEPT = 2


class GoalStatus(enum.IntEnum):
    """action_msgs/msg/GoalStatus codes."""
    UNKNOWN = 0
    ACCEPTED = 1
    EXECUTING = 2
    CANCELING = 3
    SUCCEEDED = 4
    CANCELED = 5
    ABORTED = 6


#: The selector parameter of a send-goal query that asks for the result in a second reply.
RESULT_PARAMETER = 'result'

# The expiry timer's shortest period [s], for servers that keep results briefly or not at all.
_MIN_EXPIRE_PERIOD_S = 0.1

_ACTIVE = (GoalStatus.ACCEPTED, GoalStatus.EXECUTING, GoalStatus.CANCELING)
# action_msgs/srv/CancelGoal return codes
_CANCEL_OK, _CANCEL_REJECTED, _CANCEL_UNKNOWN_GOAL, _CANCEL_TERMINATED = 0, 1, 2, 3


def default_goal_callback(goal_request: Any) -> GoalResponse:
    """Accept all goals."""
    return GoalResponse.ACCEPT


def default_cancel_callback(goal_handle: Any) -> CancelResponse:
    """Reject all cancel requests."""
    return CancelResponse.REJECT


def default_handle_accepted_callback(goal_handle: 'ServerGoalHandle') -> None:
    """Start executing the goal at once."""
    goal_handle.execute()


class ServerGoalHandle:
    """One goal on the server. Made by ActionServer only; user code gets it in callbacks."""

    def __init__(self, server: 'ActionServer', goal_id: Any, request: Any, client_id: str) -> None:
        self._server = server
        self._goal_id = goal_id
        self._request = request
        self._client_id = client_id
        self._key = goal_id.uuid.tobytes()
        self._status = GoalStatus.ACCEPTED
        self._stamp = server._node.get_clock().now().to_msg()
        self._result: Any = None
        self._finished_at: float | None = None
        self._waiters: list[DeferredResponse] = []
        self._lock = threading.Lock()

    @property
    def _status(self) -> GoalStatus:
        return self._state

    @_status.setter
    def _status(self, value: GoalStatus) -> None:
        """Every change of state is noted by the server, whose next status array rebuilds only
        the entries of the goals that changed."""
        self._state = value
        self._server._status_changed(self)

    @property
    def goal_id(self) -> Any:
        """The goal's UUID (a unique_identifier_msgs/msg/UUID), chosen by the client."""
        return self._goal_id

    @property
    def request(self) -> Any:
        """The goal message the client sent (an instance of the action's Goal)."""
        return self._request

    @property
    def status(self) -> int:
        """The goal's current status (a GoalStatus value)."""
        return int(self._status)

    @property
    def is_active(self) -> bool:
        """Whether the goal is accepted, executing or canceling (not yet ended)."""
        return self._status in _ACTIVE

    @property
    def is_executing(self) -> bool:
        """Whether the goal is executing."""
        return self._status == GoalStatus.EXECUTING

    @property
    def is_cancel_requested(self) -> bool:
        """Whether a cancel request for this goal was accepted.

        An execute callback polls this and ends the goal with `canceled()` when it is set.
        """
        return self._status == GoalStatus.CANCELING

    def execute(self, execute_callback: Callable | None = None) -> None:
        """Move to EXECUTING and run the execute callback on the executor."""
        self._server._start_execution(self, execute_callback)

    def publish_feedback(self, feedback: Any) -> None:
        """Send feedback to the client that sent the goal.

        zros publishes each client's feedback on a topic of its own, so clients of the same action
        do not receive (and decode) each other's feedback.

        :param feedback: An instance of the action's Feedback type.
        """
        self._server._publish_feedback(self, feedback)

    def succeed(self) -> None:
        """End the goal as SUCCEEDED; the execute callback then returns the result.

        :raises RuntimeError: If the goal is not executing or canceling.
        """
        self._transition(GoalStatus.SUCCEEDED, (GoalStatus.EXECUTING, GoalStatus.CANCELING))

    def abort(self) -> None:
        """End the goal as ABORTED; the execute callback then returns the result.

        :raises RuntimeError: If the goal has already ended.
        """
        self._transition(GoalStatus.ABORTED, _ACTIVE)

    def canceled(self) -> None:
        """End the goal as CANCELED, after a cancel request was accepted.

        :raises RuntimeError: If no cancel was requested.
        """
        self._transition(GoalStatus.CANCELED, (GoalStatus.CANCELING,))

    def _transition(self, new: GoalStatus, allowed: tuple) -> None:
        with self._lock:
            if self._status not in allowed:
                raise RuntimeError(f'goal {self._hex()} cannot go from {self._status.name} to {new.name}')
            self._status = new
        self._server._publish_status()

    def _request_cancel(self) -> bool:
        with self._lock:
            if self._status not in (GoalStatus.ACCEPTED, GoalStatus.EXECUTING):
                return False
            self._status = GoalStatus.CANCELING
        return True

    def _hex(self) -> str:
        return bytes(self._goal_id.uuid).hex()

    def _status_entry(self) -> tuple[bytes, bytes]:
        """This goal's action_msgs/msg/GoalStatus in wire form: (packed header, tail bytes)."""
        from interfaces.action_msgs.msg import GoalInfo, GoalStatus as GoalStatusMsg
        entry = GoalStatusMsg(goal_info=GoalInfo(goal_id=self._goal_id, stamp=self._stamp), status=int(self._status))
        head, tail = serialize_parts(entry)
        return head, b''.join(tail)


class _EndedGoal:
    """What the server keeps of a goal from its end until `result_timeout`: what the status array
    and get-result and cancel requests need. Not the goal request, as rcl keeps only the result: a
    FollowPath goal's path is most of a goal's memory, and a controller replaced every replanning
    period ends hundreds of goals within the 900 s default. User code holding the goal's
    ServerGoalHandle still has its request."""

    __slots__ = ('_goal_id', '_stamp', '_key', '_client_id', 'status', '_result', '_lock', '_waiters')
    is_active = False

    def __init__(self, handle: ServerGoalHandle) -> None:
        self._goal_id, self._stamp, self._key = handle._goal_id, handle._stamp, handle._key
        self._client_id = handle._client_id
        self.status, self._result = handle.status, handle._result
        self._lock = handle._lock
        self._waiters: list[DeferredResponse] = []   # the result is in: nobody waits any more


class ActionServer:
    """Serves one action, as rclpy.action.ActionServer.

    Goals are accepted and cancels rejected unless you give callbacks; each accepted goal's
    `execute_callback` runs as an executor task (see the module docstring).

    :param node: The node that owns the server's entities.
    :param action_type: The action class.
    :param action_name: The action's name, resolved like a service name.
    :param execute_callback: Takes a ServerGoalHandle, calls `succeed()`, `abort()` or
        `canceled()` on it and returns an instance of the action's Result.
    :param callback_group: The group of the goal, cancel and result services.
    :param goal_callback: Takes the Goal, returns a GoalResponse.
    :param handle_accepted_callback: Takes the handle of an accepted goal; by default starts it.
    :param cancel_callback: Takes the handle, returns a CancelResponse.
    :param goal_service_qos_profile: QoS of the send-goal service.
    :param result_service_qos_profile: QoS of the get-result service.
    :param cancel_service_qos_profile: QoS of the cancel service.
    :param feedback_pub_qos_profile: QoS of the feedback publishers.
    :param status_pub_qos_profile: QoS of the status publisher.
    :param result_timeout: Seconds a finished goal's result stays available.
    """

    def __init__(self, node: 'Node', action_type: Any, action_name: str, execute_callback: Callable, *,
                 callback_group: Any = None, goal_callback: Callable = default_goal_callback,
                 handle_accepted_callback: Callable = default_handle_accepted_callback,
                 cancel_callback: Callable = default_cancel_callback,
                 goal_service_qos_profile: QoSProfile = qos_profile_services_default,
                 result_service_qos_profile: QoSProfile = qos_profile_services_default,
                 cancel_service_qos_profile: QoSProfile = qos_profile_services_default,
                 feedback_pub_qos_profile: QoSProfile = QoSProfile(depth=10),
                 status_pub_qos_profile: QoSProfile = qos_profile_action_status_default,
                 result_timeout: float = 900) -> None:
        from interfaces.action_msgs.msg import GoalStatusArray
        self._node = node
        self._action_type = action_type
        self._types: Any = protocol_types(action_type)   # classes built at run time
        self._name = node.resolve_service_name(action_name)
        self._execute_callback = execute_callback
        self._goal_callback = goal_callback
        self._handle_accepted_callback = handle_accepted_callback
        self._cancel_callback = cancel_callback
        self._result_timeout = result_timeout
        self._feedback_qos = feedback_pub_qos_profile
        self.callback_group = callback_group or node.default_callback_group
        self._goal_handles: dict[bytes, ServerGoalHandle | _EndedGoal] = {}
        self._feedback_pubs: dict[str, Publisher] = {}
        self._client_goals: dict[str, int] = {}           # client id -> its goals in _goal_handles
        self._lock = threading.RLock()
        self._destroyed = False
        self._status_pending = False
        self._changed: set[ServerGoalHandle] = set()       # goals whose status entry is stale
        self._status_heads: dict[bytes, bytes] = {}         # goal key -> packed GoalStatus header
        self._status_tails: dict[bytes, bytes] = {}         # goal key -> its goal id's 16 bytes
        self._finished: deque[tuple[float, bytes]] = deque()  # (when, goal key), oldest first
        self._status_pub = Publisher(node, GoalStatusArray, f'{self._name}/_action/status',
                                     status_pub_qos_profile, self.callback_group)
        group = self.callback_group
        self._services = [
            node.create_service(self._types.SendGoalService, f'{self._name}/_action/send_goal', self._on_send_goal,
                                qos_profile=goal_service_qos_profile, callback_group=group),
            node.create_service(self._types.GetResultService, f'{self._name}/_action/get_result', self._on_get_result,
                                qos_profile=result_service_qos_profile, callback_group=group),
        ]
        self._services[0]._follow_up = self._result_too
        self._cancel_qos = cancel_service_qos_profile
        self._cancel_service: Service[Any, Any] | None = None
        if not any(s._cancel_service for s in self._siblings()):
            self._serve_cancel()
        # Finished goals are forgotten at most half a result_timeout late, while the node spins.
        self._expire_timer = node.create_timer(max(result_timeout / 2, _MIN_EXPIRE_PERIOD_S), self._on_expire_timer,
                                               callback_group=group)
        self._entity = node._declare_entity(EntityKind.ACTION_SERVER, self._name, action_type)
        node._add(self)

    @property
    def action_name(self) -> str:
        """The fully qualified (remapped) name of the action."""
        return self._name

    def get_num_entities(self) -> NumberOfEntities:
        """What the server is made of, as rclpy's Waitable reports it: three services (send goal,
        cancel, get result) and the timer that forgets expired results. The feedback and status
        publishers are not counted, as in rclpy."""
        return NumberOfEntities(num_services=3, num_timers=1)

    def _siblings(self) -> list['ActionServer']:
        """Servers of other action types under this name in this node. Endpoints are typed, as in
        ROS 2, so they share the name; the cancel service (one type for every action) is one for
        them all, served by one of them."""
        return [e for e in self._node._entities if isinstance(e, ActionServer) and e is not self
                and e._name == self._name and not e._destroyed]

    def _serve_cancel(self) -> None:
        from interfaces.action_msgs.srv import CancelGoal
        self._cancel_service = self._node.create_service(
            CancelGoal, f'{self._name}/_action/cancel_goal', self._on_cancel, qos_profile=self._cancel_qos,
            callback_group=self.callback_group)

    # -- protocol handlers (executor threads) -------------------------------------------------
    def _on_send_goal(self, request: Any, response: Any) -> Any:
        response.stamp = self._node.get_clock().now().to_msg()
        goal_id = _chosen_id(request.goal_id)
        if goal_id.uuid.tobytes() in self._goal_handles:
            return self._duplicate(response, goal_id)  # the goal callback never sees a duplicate
        try:
            decision = self._goal_callback(request.goal)
        except Exception as exc:  # noqa: BLE001 - a failing user callback rejects the goal
            self._node.get_logger().error(f"goal callback of action '{self._name}' raised {type(exc).__name__}: {exc}")
            decision = GoalResponse.REJECT
        response.accepted = decision == GoalResponse.ACCEPT
        if not response.accepted:
            return response
        handle = ServerGoalHandle(self, goal_id, request.goal, request.client_id)
        with self._lock:
            if handle._key in self._goal_handles:  # the same id came twice at once
                return self._duplicate(response, goal_id)
            self._goal_handles[handle._key] = handle
            self._client_goals[handle._client_id] = self._client_goals.get(handle._client_id, 0) + 1
        response.goal_id = goal_id
        self._feedback_publisher(request.client_id)
        self._publish_status()
        self._accept(handle)
        return response

    def _duplicate(self, response: Any, goal_id: Any) -> Any:
        """Reject a goal whose id the server already tracks, as rclpy does."""
        self._node.get_logger().error(
            f"action '{self._name}' cannot accept goal {bytes(goal_id.uuid).hex()}: the goal id already exists")
        response.accepted = False
        return response

    def _accept(self, handle: ServerGoalHandle) -> None:
        """A user's accepted-callback is called now, in the send-goal turn, so it has run when the
        client learns the goal was accepted, as with rclpy (the client has registered the goal's
        feedback callback before sending it, so feedback may come first); the default one starts
        the goal as a task of its own, after the reply (it may run long)."""
        if self._handle_accepted_callback is default_handle_accepted_callback:
            self._node._run_on_executor(self._handle_accepted, handle)
        else:
            self._handle_accepted(handle)

    def _result_too(self, query: Any, response: Any) -> DeferredResponse | None:
        """A send-goal query with the `result` parameter (a blocking `send_goal`) gets the goal's
        GetResult response as a second reply when the goal ends: one exchange instead of two."""
        if not response.accepted or RESULT_PARAMETER not in query.parameters:
            return None
        outcome = self._on_get_result(self._types.GetResultService.Request(goal_id=response.goal_id),
                                      self._types.GetResultService.Response())
        if isinstance(outcome, DeferredResponse):
            return outcome
        deferred = DeferredResponse()
        deferred.resolve(outcome)
        return deferred

    def _handle_accepted(self, handle: ServerGoalHandle) -> Any:
        try:
            if self._handle_accepted_callback is default_handle_accepted_callback:
                # Already a task on the executor: run the goal here rather than queue it
                # behind whatever else is waiting (a status flush grows with retained goals).
                return self._start_execution(handle, None, inline=True)
            self._handle_accepted_callback(handle)
        except Exception as exc:  # noqa: BLE001 - log with the goal id and abort the goal
            self._node.get_logger().error(
                f'handle_accepted_callback raised {type(exc).__name__}: {exc} (goal {handle._hex()})')
            if handle.is_active:
                handle.abort()
                self._finish(handle, self._action_type.Result())

    def _on_cancel(self, request: Any, response: Any) -> Any:
        from interfaces.action_msgs.msg import GoalInfo
        target = request.goal_info.goal_id.uuid.tobytes()
        stamp = request.goal_info.stamp
        before_ns = stamp.sec * 1_000_000_000 + stamp.nanosec
        goals: list[Any] = []
        for server in (self, *self._siblings()):
            with server._lock:
                goals.extend(server._goal_handles.values())
        if any(target):
            candidates = [g for g in goals if g._goal_id.uuid.tobytes() == target]
            if not candidates:
                response.return_code = _CANCEL_UNKNOWN_GOAL
                return response
            if before_ns:
                candidates += [g for g in goals if g not in candidates and _ns(g._stamp) <= before_ns]
        elif before_ns:
            candidates = [g for g in goals if _ns(g._stamp) <= before_ns]
        else:
            candidates = goals
        active = [g for g in candidates if g.is_active]
        if candidates and not active:
            response.return_code = _CANCEL_TERMINATED
            return response
        canceling, servers = [], set()
        for handle in active:
            try:
                decision = handle._server._cancel_callback(handle)
            except Exception as exc:  # noqa: BLE001 - a failing cancel callback rejects
                self._node.get_logger().error(f'cancel callback raised {type(exc).__name__}: {exc}')
                decision = CancelResponse.REJECT
            if decision == CancelResponse.ACCEPT and handle._request_cancel():
                canceling.append(GoalInfo(goal_id=handle.goal_id, stamp=handle._stamp))
                servers.add(handle._server)
        response.goals_canceling = canceling
        response.return_code = _CANCEL_OK if canceling or not active else _CANCEL_REJECTED
        for server in servers:
            server._publish_status()
        return response

    def _on_get_result(self, request: Any, response: Any) -> Any:
        with self._lock:
            handle = self._goal_handles.get(request.goal_id.uuid.tobytes())
        if handle is None:
            response.status = int(GoalStatus.UNKNOWN)
            return response
        with handle._lock:
            if handle._result is None:
                deferred = DeferredResponse()
                handle._waiters.append(deferred)
                return deferred
        response.status = handle.status
        response.result = handle._result
        return response

    # -- execution ---------------------------------------------------------------------------
    def _start_execution(self, handle: ServerGoalHandle, execute_callback: Callable | None,
                         inline: bool = False) -> Any:
        with handle._lock:
            status = handle._status
            if status == GoalStatus.ACCEPTED:
                handle._status = GoalStatus.EXECUTING
        if status == GoalStatus.EXECUTING:
            raise RuntimeError(f'goal {handle._hex()} is already executing')
        if status not in (GoalStatus.ACCEPTED, GoalStatus.CANCELING):
            return  # already finished
        # A goal whose cancel was accepted before it started stays CANCELING and still runs the
        # execute callback, as in rclpy: the callback sees is_cancel_requested and ends it.
        self._publish_status()
        if inline:
            return self._run(handle, execute_callback or self._execute_callback)
        else:
            self._node._run_on_executor(self._run, handle, execute_callback or self._execute_callback)

    def _run(self, handle: ServerGoalHandle, execute_callback: Callable) -> Any:
        """Run the execute callback; an `async def` one comes back as a coroutine, which the
        task running this awaits."""
        try:
            result = execute_callback(handle)
        except Exception as exc:  # noqa: BLE001 - log with the goal id, abort, keep serving
            result = self._execute_failed(handle, exc)
        if inspect.iscoroutine(result):
            return self._run_async(handle, result)
        self._conclude(handle, result)
        return None

    async def _run_async(self, handle: ServerGoalHandle, pending: Any) -> None:
        try:
            result = await pending
        except Exception as exc:  # noqa: BLE001 - log with the goal id, abort, keep serving
            result = self._execute_failed(handle, exc)
        self._conclude(handle, result)

    def _execute_failed(self, handle: ServerGoalHandle, exc: Exception) -> Any:
        """Log and abort the goal; returns what the goal concludes with: no result (None), so
        the client gets the default Result."""
        self._node.get_logger().error(
            f"execute callback of action '{self._name}' raised {type(exc).__name__}: {exc} "
            f'(goal {handle._hex()}); aborting the goal')
        if handle.is_active:
            handle._status = GoalStatus.ABORTED

    def _conclude(self, handle: ServerGoalHandle, result: Any) -> None:
        if handle.is_active:
            self._node.get_logger().warn(
                f'Goal state not set, assuming aborted. Goal ID: {handle._hex()}')
            handle._status = GoalStatus.ABORTED
        if type(result) is not self._action_type.Result:
            if result is not None:
                self._node.get_logger().error(
                    f'execute callback returned {type(result).__name__}, expected {self._action_type._TYPE} Result')
            result = self._action_type.Result()
        self._finish(handle, result)

    def _finish(self, handle: ServerGoalHandle, result: Any) -> None:
        with handle._lock:
            handle._result = result
            handle._finished_at = time.monotonic()
            waiters, handle._waiters = handle._waiters, []
        with self._lock:
            self._finished.append((handle._finished_at, handle._key))
            if self._goal_handles.get(handle._key) is handle:
                self._goal_handles[handle._key] = _EndedGoal(handle)
        response = self._types.GetResultService.Response(status=handle.status, result=result)
        for waiter in waiters:
            waiter.resolve(response)
        self._publish_status()

    def _expire_results(self) -> bool:
        """Forget goals whose results have been kept for result_timeout (checked on the server's
        one timer and on each status change, not by a timer per goal; oldest first, so the cost is
        that of the goals that expire). Returns whether any goal was forgotten."""
        cutoff = time.monotonic() - self._result_timeout
        expired = False
        unused: list[Publisher] = []
        with self._lock:
            while self._finished and self._finished[0][0] <= cutoff:
                key = self._finished.popleft()[1]
                goal = self._goal_handles.pop(key, None)
                self._status_heads.pop(key, None)
                self._status_tails.pop(key, None)
                expired = True
                if goal is not None:
                    unused += self._goal_forgotten(goal._client_id)
        for pub in unused:
            pub.destroy()
        return expired

    def _goal_forgotten(self, client_id: str) -> list[Publisher]:
        """Count one goal of `client_id` out; returns its feedback publisher once it has no goal
        left here (to destroy outside the lock). Clients come and go (each `zros action send_goal`,
        each mission script), and a publisher per client kept for the server's life would grow
        with every one. Called with the lock held."""
        left = self._client_goals.get(client_id, 1) - 1
        if left > 0:
            self._client_goals[client_id] = left
            return []
        self._client_goals.pop(client_id, None)
        pub = self._feedback_pubs.pop(client_id, None)
        return [] if pub is None else [pub]

    def _on_expire_timer(self) -> None:
        if self._expire_results():
            self._publish_status()  # the status array no longer lists them

    def _status_changed(self, handle: ServerGoalHandle) -> None:
        with self._lock:
            self._changed.add(handle)

    # -- topics -------------------------------------------------------------------------------
    def _feedback_publisher(self, client_id: str) -> Publisher:
        """The publisher of one client's feedback topic; a goal sent without a client id (by
        code written for ROS 2's protocol) gets its feedback on the one topic ROS 2 uses."""
        with self._lock:
            pub = self._feedback_pubs.get(client_id)
            if pub is None:
                topic = f'{self._name}/_action/feedback' + (f'/c{client_id}' if client_id else '')
                pub = Publisher(self._node, self._types.FeedbackMessage, topic, self._feedback_qos,
                                self.callback_group)
                self._feedback_pubs[client_id] = pub
            return pub

    def _publish_feedback(self, handle: ServerGoalHandle, feedback: Any) -> None:
        if type(feedback) is not self._action_type.Feedback:
            raise TypeError(f'publish_feedback expects {self._action_type._TYPE} Feedback, '
                            f'got {type(feedback).__name__}')
        message = self._types.FeedbackMessage(goal_id=handle.goal_id, feedback=feedback)
        self._feedback_publisher(handle._client_id).publish(message)

    def _publish_status(self) -> None:
        """Publish the status array soon: once for all the changes made by the callback that is
        running now, and after its reply has gone out (the array grows with retained goals)."""
        with self._lock:
            if self._status_pending or self._destroyed:
                return
            self._status_pending = True
        self._node._run_on_executor(self._flush_status)

    def _flush_status(self) -> None:
        """Publish the GoalStatusArray of the retained goals: its wire form is joined from each
        goal's cached entry ([status_list] then the goal ids' bytes), and only the entries of
        goals that changed are rebuilt, so a flush costs little however many goals are kept."""
        with self._lock:
            self._status_pending = False
            if self._destroyed:
                return
            self._expire_results()
            for goal in self._changed:
                if goal._key in self._goal_handles:
                    self._status_heads[goal._key], self._status_tails[goal._key] = goal._status_entry()
            self._changed.clear()
            payload = (packed_array([packed_array(list(self._status_heads.values()))])
                       + b''.join(self._status_tails.values()))
        try:
            self._status_pub.publish(payload)
        except RuntimeError:
            pass  # destroyed while a goal was finishing

    def destroy(self) -> None:
        """Destroy the server's services and publishers and leave the graph.

        Calling it twice is harmless; `Node.destroy_node` calls it too.
        """
        if self._destroyed:
            return
        self._destroyed = True
        self._node._forget(self)
        self._node._undeclare_entity(self._entity)
        for service in self._services:
            self._node.destroy_service(service)
        self._node.destroy_timer(self._expire_timer)
        if self._cancel_service is not None:
            self._node.destroy_service(self._cancel_service)
            siblings = self._siblings()
            if siblings and not self._node._destroyed:
                siblings[0]._serve_cancel()
        with self._lock:
            pubs = list(self._feedback_pubs.values())
            self._feedback_pubs.clear()
            goals = list(self._goal_handles.values())
        for pub in pubs:
            pub.destroy()
        self._status_pub.destroy()
        for handle in goals:
            with handle._lock:
                waiters, handle._waiters = handle._waiters, []
            for waiter in waiters:
                waiter.fail(f"action server '{self._name}' was destroyed")


def _chosen_id(goal_id: Any) -> Any:
    """The id a goal request asks for, or a new UUID4 if it asks for none (all zeros)."""
    from interfaces.unique_identifier_msgs.msg import UUID
    return goal_id if any(goal_id.uuid) else UUID(uuid=uuid.uuid4().bytes)


def _ns(stamp: Any) -> int:
    return stamp.sec * 1_000_000_000 + stamp.nanosec
