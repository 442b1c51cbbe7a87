"""bt_navigator's follow-while-replanning loop, with its action calls scripted (no processes).

A FollowPath goal that ends while the navigator is computing the next path is the outcome, as
in Nav2's tree (its PipelineSequence ticks FollowPath again after ComputePathToPose). Replacing
it with a new FollowPath lost the success: over a slow link, or on a loaded machine, the robot
sat at its goal while the controller said "Reached the goal!" to one new path after another.
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
        Call.sent.append(self)

    def poll(self) -> bool:
        return self.status is not None

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
