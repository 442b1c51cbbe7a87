"""Action clients (rclpy.action.ActionClient's interface).

The client subscribes at creation to its own feedback topic (the server sends a client only
the feedback of its own goals), to the action's shared feedback topic (where a server speaking
ROS 2's protocol, with no client ids, sends all feedback) and to the status topic. The client
picks each goal's id (UUID4), as rclpy does. The get-result request has no
timeout, so arbitrarily long goals are fine; if the server dies, Zenoh finalizes the request
and the result future fails with a clear error instead of hanging.
"""
from __future__ import annotations

import os
import threading
import time
import uuid
import weakref
from typing import TYPE_CHECKING, Any, Callable

from zros.action.counts import NumberOfEntities
from zros.action.server import RESULT_PARAMETER, GoalStatus
from zros.action_types import protocol_types
from zros.errors import ServiceCallError
from zros.graph import EntityKind
from zros.qos import QoSProfile, qos_profile_action_status_default, qos_profile_services_default
from zros.task import Future

if TYPE_CHECKING:
    from zros.client import Client
    from zros.node import Node

__all__ = ['ActionClient', 'ClientGoalHandle']

# Feedback and the result travel separately: the result (completed on Zenoh's thread) can be
# processed before feedback that arrived earlier and waits for the executor. A finished goal's
# feedback callback therefore still gets feedback that arrived before the result, and is
# forgotten this long after it [s].
_SETTLED_MEMORY_S = 2.0


class ClientGoalHandle:
    """A goal as the client sees it; made by ActionClient."""

    def __init__(self, client: 'ActionClient', goal_id: Any, stamp: Any, accepted: bool) -> None:
        self._client = client
        self._goal_id = goal_id
        self._stamp = stamp
        self._accepted = accepted
        self._status = GoalStatus.ACCEPTED if accepted else GoalStatus.UNKNOWN

    @property
    def goal_id(self) -> Any:
        """The goal's UUID (a unique_identifier_msgs/msg/UUID), chosen by the client."""
        return self._goal_id

    @property
    def stamp(self) -> Any:
        """When the server accepted the goal (builtin_interfaces/msg/Time from its clock)."""
        return self._stamp

    @property
    def accepted(self) -> bool:
        """Whether the server accepted the goal."""
        return self._accepted

    @property
    def status(self) -> int:
        """The goal's latest status (a GoalStatus value), as the server's status topic reports it.

        It is UNKNOWN for a rejected goal and moves on as status messages arrive on the executor.
        """
        return int(self._status)

    def get_result_async(self) -> Future:
        """Ask the server for the goal's result.

        The server answers when the goal ends, however long it runs.

        :return: A Future completed with the GetResult response (`.status`, `.result`).
        :raises RuntimeError: If the goal was not accepted.
        """
        if not self._accepted:
            raise RuntimeError('cannot get the result of a goal that was not accepted')
        return self._client._get_result_async(self)

    def get_result(self) -> Any:
        """Blocking: the GetResult response (`.status`, `.result`)."""
        future = self.get_result_async()
        future.wait()
        return future.result()

    def cancel_goal_async(self) -> Future:
        """Ask the server to cancel this goal.

        :return: A Future completed with the action_msgs/srv/CancelGoal response (its
            `goals_canceling` lists the goal if the server accepted the cancel).
        """
        return self._client._cancel_goal_async(self)

    def cancel_goal(self) -> Any:
        """Blocking: ask the server to cancel this goal and wait for its answer.

        Waits on the future, not by spinning: zros completes service replies on Zenoh's thread.

        :return: The action_msgs/srv/CancelGoal response.
        """
        future = self.cancel_goal_async()
        future.wait()
        return future.result()

    def __repr__(self) -> str:
        return f'ClientGoalHandle(goal_id={bytes(self._goal_id.uuid).hex()}, accepted={self._accepted})'


class ActionClient:
    """Sends goals to one action server, as rclpy.action.ActionClient.

    The client is three service clients (send goal, cancel, get result) and two subscriptions
    (feedback, status) under ``<action>/_action/``. Unlike rclpy, feedback comes on a topic of
    this client's own, so clients of a busy action do not decode each other's feedback.

    :param node: The node that owns the client's entities.
    :param action_type: The action class, e.g. ``Fibonacci`` from ``interfaces.example_interfaces.action``.
    :param action_name: The action's name, resolved like a service name.
    :param callback_group: The group for feedback, status and done callbacks; the node's
        default group if ``None``.
    :param goal_service_qos_profile: QoS of the send-goal client.
    :param result_service_qos_profile: QoS of the get-result client.
    :param cancel_service_qos_profile: QoS of the cancel client.
    :param feedback_sub_qos_profile: QoS of the feedback subscription.
    :param status_sub_qos_profile: QoS of the status subscription.
    """

    def __init__(self, node: 'Node', action_type: Any, action_name: str, *, callback_group: Any = None,
                 goal_service_qos_profile: QoSProfile = qos_profile_services_default,
                 result_service_qos_profile: QoSProfile = qos_profile_services_default,
                 cancel_service_qos_profile: QoSProfile = qos_profile_services_default,
                 feedback_sub_qos_profile: QoSProfile = QoSProfile(depth=100),
                 status_sub_qos_profile: QoSProfile = qos_profile_action_status_default) -> None:
        from interfaces.action_msgs.msg import GoalStatusArray
        from interfaces.action_msgs.srv import CancelGoal
        self._node = node
        self._action_type = action_type
        self._types: Any = protocol_types(action_type)   # classes built at run time
        self._name = node.resolve_service_name(action_name)
        self.callback_group = callback_group or node.default_callback_group
        self._client_id = os.urandom(8).hex()
        self._lock = threading.Lock()
        self._feedback_callbacks: dict[bytes, Callable] = {}
        # Weak, as in rclpy: a goal whose result nobody asks for (a navigator replacing its
        # FollowPath goal every replanning period) is forgotten with its last handle.
        self._handles: weakref.WeakValueDictionary[bytes, ClientGoalHandle] = weakref.WeakValueDictionary()
        self._settled: dict[bytes, int] = {}   # goal key -> when its result came [ns, wall clock]
        group = self.callback_group
        self._send_client: Client[Any, Any] = node.create_client(
            self._types.SendGoalService, f'{self._name}/_action/send_goal',
            qos_profile=goal_service_qos_profile, callback_group=group)
        self._cancel_client = node.create_client(CancelGoal, f'{self._name}/_action/cancel_goal',
                                                 qos_profile=cancel_service_qos_profile, callback_group=group)
        self._result_client: Client[Any, Any] = node.create_client(
            self._types.GetResultService, f'{self._name}/_action/get_result',
            qos_profile=result_service_qos_profile, callback_group=group)
        self._feedback_subs = [node.create_subscription(
            self._types.FeedbackMessage, topic, self._on_feedback, feedback_sub_qos_profile, callback_group=group)
            for topic in (f'{self._name}/_action/feedback/c{self._client_id}', f'{self._name}/_action/feedback')]
        self._status_sub = node.create_subscription(
            GoalStatusArray, f'{self._name}/_action/status', self._on_status, status_sub_qos_profile,
            callback_group=group)
        self._entity = node._declare_entity(EntityKind.ACTION_CLIENT, self._name, action_type)
        self._destroyed = False
        node._add(self)

    @property
    def action_name(self) -> str:
        """The fully qualified (remapped) name of the action."""
        return self._name

    def get_num_entities(self) -> NumberOfEntities:
        """What the client is made of, as rclpy's Waitable reports it: three service clients (send
        goal, cancel, get result) and two subscriptions, feedback and status (zros's feedback is
        one channel on two topics, the client's own and the shared one)."""
        return NumberOfEntities(num_subscriptions=2, num_clients=3)

    def _listed(self, entities: list) -> bool:
        """Whether the graph lists the action's three services, each of its type (servers of other
        action types may share the name), as rclpy requires. A server need not be a zros
        ActionServer: services made from the action's `Impl` types serve it too."""
        served = {(e.name, e.type) for e in entities if e.kind == EntityKind.SERVICE}
        return all((c.srv_name, c.srv_type._TYPE) in served for c in self._service_clients())

    def _service_clients(self) -> tuple:
        return self._send_client, self._cancel_client, self._result_client

    def server_is_ready(self) -> bool:
        """A goal sent now is delivered: the server and its services are in the graph and Zenoh's
        routing knows their queryables (see zros.client)."""
        return (self._listed(self._node.context.graph.entities())
                and all(c.service_is_ready() for c in self._service_clients()))

    def wait_for_server(self, timeout_sec: float | None = None) -> bool:
        """Wait until an action server with this name is in the graph and its services are reachable.

        :param timeout_sec: Seconds to wait at most; ``None`` waits forever.
        :return: ``True`` if the server is ready, ``False`` on timeout.
        """
        deadline = None if timeout_sec is None else time.monotonic() + timeout_sec
        graph = self._node.context.graph
        while True:
            left = None if deadline is None else max(0.0, deadline - time.monotonic())
            if not graph.wait_for(self._listed, left):
                return False
            for client in self._service_clients():
                left = None if deadline is None else max(0.0, deadline - time.monotonic())
                if not client.wait_for_service(left):
                    return False
            if self.server_is_ready():  # the server may have gone meanwhile
                return True

    # -- goals ---------------------------------------------------------------------------------
    def send_goal_async(self, goal: Any, feedback_callback: Callable | None = None,
                        goal_uuid: Any = None) -> Future:
        """Send a goal and return at once.

        :param goal: An instance of the action's Goal type.
        :param feedback_callback: Called on the executor with each FeedbackMessage of this goal.
        :param goal_uuid: The goal's id (a unique_identifier_msgs/msg/UUID); the server picks one if ``None``.
        :return: A Future completed with a ClientGoalHandle (check its `accepted`).
        :raises TypeError: If `goal` is not the action's Goal.
        """
        request = self._goal_request(goal, goal_uuid, feedback_callback)
        outer: Future[ClientGoalHandle] = Future(node=self._node)
        inner = self._send_client.call_async(request)

        def on_response(done: Future[Any]) -> None:
            exc = done.exception()
            if exc is not None:
                self._forget(request.goal_id)
                outer.set_exception(exc)
                return
            outer.set_result(self._register(request.goal_id, done.result()))
        inner.add_done_callback(on_response)
        return outer

    def _goal_request(self, goal: Any, goal_uuid: Any, feedback_callback: Callable | None) -> Any:
        """The send-goal request for `goal`, with the caller's goal id or a new UUID4. The feedback
        callback is registered before the request leaves: feedback can overtake the reply.

        :raises TypeError: If `goal` is not the action's Goal.
        """
        from interfaces.unique_identifier_msgs.msg import UUID
        if type(goal) is not self._action_type.Goal:
            raise TypeError(f"action '{self._name}' expects {self._action_type._TYPE} Goal, "
                            f'got {getattr(type(goal), "_TYPE", type(goal).__name__)}')
        goal_id = goal_uuid if goal_uuid is not None else UUID(uuid=uuid.uuid4().bytes)
        request = self._types.SendGoalService.Request(goal_id=goal_id, goal=goal, client_id=self._client_id)
        if feedback_callback is not None:
            with self._lock:
                self._feedback_callbacks[request.goal_id.uuid.tobytes()] = feedback_callback
        return request

    def _register(self, goal_id: Any, response: Any) -> ClientGoalHandle:
        """The handle of a goal the server answered; an accepted goal is tracked for its status.
        The goal keeps the id the client chose (a ROS 2 server's reply carries none)."""
        handle = ClientGoalHandle(self, goal_id, response.stamp, response.accepted)
        if not response.accepted:
            self._forget(goal_id)
            return handle
        with self._lock:
            self._handles[goal_id.uuid.tobytes()] = handle
        return handle

    def _forget(self, goal_id: Any) -> None:
        """Drop the feedback callback of a goal the server never took."""
        with self._lock:
            self._feedback_callbacks.pop(goal_id.uuid.tobytes(), None)

    def _settle(self, handle: ClientGoalHandle, response: Any) -> None:
        """The goal's result is in: record its status and stop tracking it. Feedback that arrived
        before now still reaches the goal's callback; later feedback does not, as in rclpy."""
        handle._status = GoalStatus(response.status)
        key = handle.goal_id.uuid.tobytes()
        with self._lock:
            self._handles.pop(key, None)
            self._note_settled(key, time.time_ns())

    def _note_settled(self, key: bytes, now: int) -> None:
        """Record that goal `key` ended at `now` [ns, wall clock] and forget the feedback callbacks
        of goals that ended more than _SETTLED_MEMORY_S ago. Called with the lock held."""
        self._settled.setdefault(key, now)
        for old, when in list(self._settled.items()):
            if now - when > _SETTLED_MEMORY_S * 1e9:
                del self._settled[old]
                self._feedback_callbacks.pop(old, None)

    def send_goal(self, goal: Any, feedback_callback: Callable | None = None, goal_uuid: Any = None) -> Any:
        """Send a goal and block until it ends.

        Both answers (acceptance, result) are read on this thread, so no executor is needed;
        feedback callbacks still need the node to be spun, as in rclpy.

        :param goal: An instance of the action's Goal type.
        :param feedback_callback: Called on the executor with each FeedbackMessage of this goal.
        :param goal_uuid: The goal's id; the server picks one if ``None``.
        :return: The GetResult response (`.status`, `.result`), or ``None`` if the goal was rejected.
        :raises TypeError: If `goal` is not the action's Goal.
        :raises ServiceCallError: If the server cannot be reached.
        """
        request = self._goal_request(goal, goal_uuid, feedback_callback)
        # One query: the server replies with the acceptance, then with the result when the goal
        # ends. A server that answers only the acceptance is asked for the result separately.
        replies = self._send_client._replies(
            request, None,
            (self._types.SendGoalService.Response, self._types.GetResultService.Response), RESULT_PARAMETER)
        try:
            response = next(replies)
        except ServiceCallError:
            self._forget(request.goal_id)
            raise
        handle = self._register(request.goal_id, response)
        if not handle.accepted:
            return None
        try:
            result = next(replies)
        except ServiceCallError:
            try:
                result = self._result_client.call(self._types.GetResultService.Request(goal_id=handle.goal_id))
            except ServiceCallError as exc:
                raise ServiceCallError(f"action server '{self._name}' did not deliver the result of goal "
                                       f'{bytes(handle.goal_id.uuid).hex()}: {exc}') from None
        self._settle(handle, result)
        return result

    def _get_result_async(self, handle: ClientGoalHandle) -> Future:
        outer: Future[Any] = Future(node=self._node)
        inner = self._result_client.call_async(self._types.GetResultService.Request(goal_id=handle.goal_id))
        name = self._name

        def on_result(done: Future) -> None:
            exc = done.exception()
            if exc is not None:
                outer.set_exception(ServiceCallError(
                    f"action server '{name}' did not deliver the result of goal "
                    f'{bytes(handle.goal_id.uuid).hex()}: {exc}'))
                return
            response = done.result()
            self._settle(handle, response)
            outer.set_result(response)
        inner.add_done_callback(on_result)
        return outer

    def _cancel_goal_async(self, handle: ClientGoalHandle) -> Future:
        from interfaces.action_msgs.msg import GoalInfo
        from interfaces.action_msgs.srv import CancelGoal
        return self._cancel_client.call_async(CancelGoal.Request(goal_info=GoalInfo(goal_id=handle.goal_id)))

    # -- topics (executor) ---------------------------------------------------------------------
    def _on_feedback(self, message: Any, info: Any) -> None:
        """Hand feedback to its goal's callback, unless it came after the goal's result (or is
        for a goal this client did not send, or sent without a callback). Before the result
        means received before it, or sent before it (the server's stamp, on the same wall clock
        when both run on one machine): feedback and result come through different channels, and
        under load the thread that stamps a sample's arrival may get to it after the result was
        taken, although the server sent it first."""
        key = message.goal_id.uuid.tobytes()
        with self._lock:
            callback = self._feedback_callbacks.get(key)
            settled = self._settled.get(key)
        if callback is not None and (settled is None or info['received_timestamp'] <= settled
                                     or 0 < info['source_timestamp'] <= settled):
            callback(message)

    def _on_status(self, array: Any) -> None:
        """Update the handles' status; a goal the server reports ended is settled here too, so
        the feedback callback of a goal whose result is never asked for is forgotten as well."""
        now = time.time_ns()
        with self._lock:
            for status in array.status_list:
                key = status.goal_info.goal_id.uuid.tobytes()
                handle = self._handles.get(key)
                if handle is not None:
                    handle._status = GoalStatus(status.status)
                if status.status >= GoalStatus.SUCCEEDED and key in self._feedback_callbacks:
                    self._note_settled(key, now)

    def destroy(self) -> None:
        """Destroy the client's services and subscriptions and leave the graph.

        Calling it twice is harmless; `Node.destroy_node` calls it too.
        """
        if self._destroyed:
            return
        self._destroyed = True
        self._node._forget(self)
        self._node._undeclare_entity(self._entity)
        for entity in (self._send_client, self._cancel_client, self._result_client, *self._feedback_subs,
                       self._status_sub):
            self._node._destroy_entity(entity)
