"""bt_navigator's follow-while-replanning loop, with its action calls scripted (no processes).

A FollowPath goal that ends while the navigator is computing the next path is the outcome, as
in Nav2's tree (its PipelineSequence ticks FollowPath again after ComputePathToPose). Replacing
it with a new FollowPath lost the success: over a slow link, or on a loaded machine, the robot
sat at its goal while the controller said "Reached the goal!" to one new path after another.
Nor is a goal the status topic reports ended replaced while its result is on its way (Nav2's
BtActionNode sends an updated goal only while the old one is ACCEPTED or EXECUTING).
"""
from __future__ import annotations

from types import SimpleNamespace

from interfaces.action_msgs.msg import GoalStatus
from interfaces.nav2_msgs.action import NavigateToPose
from interfaces.nav_msgs.msg import Path
from nodes.nav2_bt_navigator import bt_navigator


class Clock:
    def __init__(self) -> None:
        self.ns = 0

    def now(self) -> SimpleNamespace:
        return SimpleNamespace(nanoseconds=self.ns)


class Rate:
    """Each sleep is half a second of the navigator's clock."""

    def __init__(self, clock: Clock) -> None:
        self.clock = clock

    def sleep(self) -> None:
        self.clock.ns += 500_000_000

    def destroy(self) -> None:
        pass


class Call:
    """A FollowPath goal that stays running until the test ends it."""

    sent: list['Call'] = []

    def __init__(self, client, goal) -> None:
        self.status = None
        self.result = None
        self.reported_ended = False     # the status topic said it ended; its result is still on its way
        Call.sent.append(self)

    def poll(self) -> bool:
        return self.status is not None

    @property
    def running(self) -> bool:
        return self.status is None and not self.reported_ended

    def cancel(self) -> None:
        self.status = GoalStatus.STATUS_CANCELED


def navigation(monkeypatch, compute_path) -> bt_navigator.Navigation:
    clock = Clock()
    server = SimpleNamespace(number_of_retries=6, get_clock=lambda: clock, create_rate=lambda hz: Rate(clock),
                             replan_frequency=1.0, loop_frequency=20.0, follow_client=None,
                             slot=SimpleNamespace(is_current=lambda handle: True),
                             current_state=SimpleNamespace(label='active'), get_logger=None, clear=lambda which: None)
    handle = SimpleNamespace(request=NavigateToPose.Goal(), is_cancel_requested=False)
    Call.sent = []
    monkeypatch.setattr(bt_navigator, 'GoalCall', Call)
    nav = bt_navigator.Navigation(server, handle, [None])
    nav.publish_feedback = lambda: None
    nav.compute_path = compute_path
    return nav


def test_a_follow_goal_that_succeeds_while_replanning_is_the_outcome(monkeypatch):
    plans = []

    def compute_path():
        plans.append(1)
        if len(plans) == 2:                 # the replan: meanwhile the controller reached the goal
            Call.sent[0].status = GoalStatus.STATUS_SUCCEEDED
        return bt_navigator.Outcome('SUCCEEDED'), Path()
    nav = navigation(monkeypatch, compute_path)
    assert nav.follow_with_replanning().state == 'SUCCEEDED'
    assert len(Call.sent) == 1, 'a new FollowPath replaced the one that had succeeded'


def test_a_follow_goal_that_fails_while_replanning_fails_the_attempt(monkeypatch):
    plans = []

    def compute_path():
        plans.append(1)
        if len(plans) == 2:
            Call.sent[0].status = GoalStatus.STATUS_ABORTED
            Call.sent[0].result = SimpleNamespace(error_code=105, error_msg='Failed to make progress')
        return bt_navigator.Outcome('SUCCEEDED'), Path()
    nav = navigation(monkeypatch, compute_path)
    outcome = nav.follow_with_replanning()
    assert (outcome.state, outcome.code) == ('FAILED', 105)
    assert len(Call.sent) == 1


def test_a_running_follow_goal_gets_each_new_path(monkeypatch):
    plans = []

    def compute_path():
        plans.append(1)
        if len(plans) == 4:
            Call.sent[-1].status = GoalStatus.STATUS_SUCCEEDED
        return bt_navigator.Outcome('SUCCEEDED'), Path()
    nav = navigation(monkeypatch, compute_path)
    assert nav.follow_with_replanning().state == 'SUCCEEDED'
    assert len(Call.sent) == 3      # the first path, and one per replan while it ran


def test_a_follow_goal_reported_ended_is_waited_for_not_replaced(monkeypatch):
    """At a fast replanning rate, or with a slow result round trip, the next plan comes before the
    ended goal's result: replacing it then made a new goal that ended the same way, forever."""
    plans = []

    def compute_path():
        plans.append(1)
        if len(plans) == 2:
            Call.sent[0].reported_ended = True          # the status array says SUCCEEDED
        elif len(plans) == 5:
            Call.sent[0].status = GoalStatus.STATUS_SUCCEEDED   # its result arrives three plans later
        return bt_navigator.Outcome('SUCCEEDED'), Path()
    nav = navigation(monkeypatch, compute_path)
    assert nav.follow_with_replanning().state == 'SUCCEEDED'
    assert len(Call.sent) == 1


class _Handle:
    def __init__(self, status: int) -> None:
        self.status, self.accepted = status, True

    def get_result_async(self):
        return _Future(None, done=False)


class _Future:
    def __init__(self, value, done: bool = True) -> None:
        self.value, self._done = value, done

    def done(self) -> bool:
        return self._done

    def result(self):
        return self.value


def test_goal_call_is_running_until_the_status_topic_reports_its_end():
    from zros.navigation.servers import GoalCall
    handle = _Handle(GoalStatus.STATUS_ACCEPTED)
    sent = _Future(handle, done=False)
    call = GoalCall(SimpleNamespace(send_goal_async=lambda goal, feedback_callback: sent), goal=None)
    assert call.running and not call.poll()          # not answered yet
    sent._done = True
    assert not call.poll() and call.running          # accepted
    handle.status = GoalStatus.STATUS_EXECUTING
    assert call.running
    handle.status = GoalStatus.STATUS_SUCCEEDED      # reported ended, result not in yet
    assert not call.poll() and not call.running


def test_a_goal_given_up_before_its_send_failed_is_not_cancelled():
    """GoalCall.cancel() on a goal not answered yet cancels it once accepted; if the send fails
    (no server), the done callback must not raise: it runs on the node's executor."""
    from zros.navigation.servers import GoalCall

    class Sent(_Future):
        def __init__(self) -> None:
            super().__init__(None, done=False)
            self.callbacks, self.error = [], None

        def add_done_callback(self, callback):
            self.callbacks.append(callback)

        def exception(self):
            return self.error

        def result(self):
            if self.error is not None:
                raise self.error
            return self.value
    failed, accepted = Sent(), Sent()
    cancelled = []
    accepted.value = SimpleNamespace(accepted=True, cancel_goal_async=lambda: cancelled.append(1))
    for sent in (failed, accepted):
        GoalCall(SimpleNamespace(send_goal_async=lambda goal, feedback_callback: sent), goal=None).cancel()
    failed.error = RuntimeError('no server')
    for sent in (failed, accepted):
        for callback in sent.callbacks:
            callback(sent)
    assert cancelled == [1]
