"""What every navigation server node shares: lifecycle gating of goals, one goal at a time with
preemption, failing a goal with Nav2's error code, the goal loop, and a non-blocking action
call for servers that drive other servers.

Nav2's servers (nav2_util::SimpleActionServer) run one goal at a time; a new goal preempts the
running one, which ends ABORTED. Here each goal's execute callback runs its own loop on the
multi-threaded executor; `GoalSlot` tells a loop when a newer goal has taken over, and
`GoalRunner` is the loop every server runs (preemption, cancel, shutdown, failure).
"""
from __future__ import annotations

import threading
from typing import Any, Callable

from zros.exceptions import ROSInterruptException

from zros.action import ActionServer, CancelResponse, GoalResponse
from zros.callback_groups import ReentrantCallbackGroup

__all__ = ['GoalSlot', 'GoalRunner', 'gated_action_server', 'GoalCall', 'missed_rate_message', 'RESULT_TIMEOUT_S',
           'MISSION_RESULT_TIMEOUT_S']


class GoalSlot:
    """The goal a server is working on; `take(handle)` makes `handle` current, `is_current(handle)`
    is how an older loop learns it has been preempted."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._current: Any = None

    def take(self, handle: Any) -> Any:
        with self._lock:
            previous, self._current = self._current, handle
            return previous

    def is_current(self, handle: Any) -> bool:
        with self._lock:
            return self._current is handle

    def release(self, handle: Any) -> None:
        with self._lock:
            if self._current is handle:
                self._current = None

    @property
    def current(self) -> Any:
        with self._lock:
            return self._current


class GoalRunner:
    """A server's goals: its `slot`, failing a goal, and the loop a goal runs.

    `stop` (e.g. publish a zero Twist) runs when the current goal is canceled or fails; a goal
    that was preempted leaves the robot to the goal that replaced it.
    """

    def __init__(self, node: Any, stop: Callable[[], None] | None = None) -> None:
        self.node = node
        self.slot = GoalSlot()
        self._stop = stop

    def stop_if_current(self, handle: Any) -> None:
        if self._stop is not None and (self.slot.current is None or self.slot.is_current(handle)):
            self._stop()

    def fail(self, handle: Any, result: Any, code: int, message: str) -> Any:
        """Abort the goal with Nav2's error code and message (when its result has them), logged."""
        self.node.get_logger().warn(f'{message} (error code {code})')
        if hasattr(result, 'error_code'):
            result.error_code = code
        if hasattr(result, 'error_msg'):     # nav2_route's results have a code only
            result.error_msg = message
        self.stop_if_current(handle)
        handle.abort()
        return result

    def loop(self, handle: Any, result: Any, frequency: float, step: Callable[[], Any],
             on_interrupt: Callable[[], None] | None = None, *, report_missed_rate: bool = False) -> Any:
        """Call `step()` at `frequency` until it returns the goal's result (it has ended the goal);
        a newer goal aborts this one, a cancel request stops the robot and cancels it, shutdown
        aborts it (`on_interrupt` runs first in those cases: cancel what the goal started).
        The slot is released however the loop ends.

        `report_missed_rate` warns, as Nav2's controller_server does, when one step takes longer
        than the period (on the node's clock), at most once a second: on a busy machine the loop
        runs slower rather than failing, and the log says so."""
        rate = self.node.create_rate(frequency)
        clock = self.node.get_clock()
        try:
            while True:
                preempted = not self.slot.is_current(handle)
                if preempted or handle.is_cancel_requested:
                    if on_interrupt is not None:
                        on_interrupt()
                if preempted:
                    if hasattr(result, 'error_msg'):
                        result.error_msg = 'preempted by a new goal'
                    handle.abort()
                    return result
                if handle.is_cancel_requested:
                    self.stop_if_current(handle)
                    handle.canceled()
                    return result
                started = clock.now().nanoseconds if report_missed_rate else 0
                done = step()
                if done is not None:
                    return done
                if report_missed_rate:
                    self._check_rate(frequency, (clock.now().nanoseconds - started) / 1e9)
                rate.sleep()
        except ROSInterruptException:
            handle.abort()
            return result
        finally:
            rate.destroy()
            self.slot.release(handle)


    def _check_rate(self, frequency: float, elapsed_s: float) -> None:
        message = missed_rate_message(frequency, elapsed_s)
        if message is not None:
            self.node.get_logger().warn(message, throttle_duration_sec=1.0)


def missed_rate_message(frequency: float, elapsed_s: float) -> str | None:
    """Nav2's warning for a control step of `elapsed_s` seconds in a loop meant to run at
    `frequency` Hz, or None when the step fit in its period."""
    if elapsed_s <= 1.0 / frequency:
        return None
    return (f'Control loop missed its desired rate of {frequency:.4f} Hz. '
            f'Current loop rate is {1.0 / elapsed_s:.4f} Hz.')


#: Seconds an ended goal's result stays available, Nav2's `action_server_result_timeout` default
#: (Jazzy) in the servers a navigator sends a goal every replanning period (planner, controller,
#: smoother, behaviors, route, docking): rcl's 900 s would keep every replaced FollowPath and
#: every computed path of the last 15 minutes, and send them all in each status array.
RESULT_TIMEOUT_S = 10.0
#: The same for the servers a user's mission calls (bt_navigator, waypoint_follower): rcl's default.
MISSION_RESULT_TIMEOUT_S = 900.0


def gated_action_server(node: Any, action_type: type, name: str, execute: Callable[[Any], Any], *,
                        result_timeout: float = RESULT_TIMEOUT_S) -> ActionServer:
    """An action server that accepts goals only while the lifecycle node is active, and accepts
    cancel requests (rclpy's default refuses them). `result_timeout` is the node's
    `action_server_result_timeout` parameter, as in Nav2."""
    def goal_callback(goal: Any) -> GoalResponse:
        if node.current_state.label != 'active':
            node.get_logger().warn(f"Action server '{name}' is inactive: rejecting the goal (is the lifecycle manager up?)")
            return GoalResponse.REJECT
        return GoalResponse.ACCEPT

    return ActionServer(node, action_type, name, execute, goal_callback=goal_callback,
                        cancel_callback=lambda handle: CancelResponse.ACCEPT,
                        callback_group=ReentrantCallbackGroup(), result_timeout=result_timeout)


class GoalCall:
    """One goal sent to another action server, polled from a loop without blocking it.

    `poll()` returns True once the goal has finished (or was rejected); then `status` (an
    action_msgs GoalStatus code) and `result` are set.
    """

    def __init__(self, client: Any, goal: Any, feedback_callback: Callable | None = None) -> None:
        self.status: int | None = None
        self.result: Any = None
        self.feedback: Any = None
        self._handle: Any = None
        self._result_future: Any = None
        self._user_feedback = feedback_callback
        self._send_future = client.send_goal_async(goal, feedback_callback=self._on_feedback)

    def _on_feedback(self, msg: Any) -> None:
        self.feedback = msg.feedback
        if self._user_feedback is not None:
            self._user_feedback(msg.feedback)

    def poll(self) -> bool:
        from interfaces.action_msgs.msg import GoalStatus
        if self.status is not None:
            return True
        if self._result_future is None:
            if not self._send_future.done():
                return False
            self._handle = self._send_future.result()
            if self._handle is None or not self._handle.accepted:
                self.status = GoalStatus.STATUS_ABORTED
                return True
            self._result_future = self._handle.get_result_async()
        if not self._result_future.done():
            return False
        response = self._result_future.result()
        self.status, self.result = response.status, response.result
        return True

    @property
    def running(self) -> bool:
        """Whether the goal may still be running: not answered yet, or accepted and not reported
        ended on the action's status topic. A navigator replaces only a running goal with an
        updated one, as Nav2's BtActionNode does (it sends the new path only while the old goal is
        ACCEPTED or EXECUTING): a goal that has ended is waited for, so its success is not lost to
        a replacement that ends the same way, and so on at every replanning period."""
        from interfaces.action_msgs.msg import GoalStatus
        if self.status is not None:
            return False
        return self._handle is None or self._handle.status in (GoalStatus.STATUS_ACCEPTED,
                                                               GoalStatus.STATUS_EXECUTING)

    def cancel(self) -> None:
        if self._handle is not None and self.status is None:
            self._handle.cancel_goal_async()
        elif self._handle is None:
            self._send_future.add_done_callback(_cancel_once_accepted)


def _cancel_once_accepted(sent: Any) -> None:
    """Cancel a goal whose acceptance was still on its way when the caller gave it up. The send
    may have failed instead (no server: a link drop-out), which leaves nothing to cancel; raising
    here would end the spin of the executor that runs the callback, and the node with it."""
    if sent.exception() is None and sent.result() is not None and sent.result().accepted:
        sent.result().cancel_goal_async()
