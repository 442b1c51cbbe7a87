"""benchmarks/link.py's bookkeeping of navigation over a bad link and of the soak: which failed
attempts the drop-outs caused (those a mission sends again), the goal figures, memory growth after
the warm-up, missing numbers of a reliable stream, and the seeded goals themselves."""
from __future__ import annotations

import math

import pytest

from benchmarks.link import failed_by_drop, goal_summary, link_goals, memory_growth, missing_sequence


def test_an_attempt_running_through_a_drop_out_is_the_drop_outs():
    assert failed_by_drop(100.0, 130.0, [(110.0, 115.0)])


def test_an_attempt_failing_soon_after_the_link_returned_is_still_the_drop_outs():
    # localization and the costmaps are catching up on the backlog for a few seconds
    assert failed_by_drop(118.0, 125.0, [(110.0, 115.0)], grace=10.0)


def test_an_attempt_far_from_any_drop_out_failed_by_itself():
    assert not failed_by_drop(130.0, 150.0, [(110.0, 115.0)], grace=10.0)
    assert not failed_by_drop(100.0, 109.0, [(110.0, 115.0), (170.0, 175.0)])
    assert not failed_by_drop(100.0, 109.0, [])


def _attempt(outcome: str, sim_s: float, drop: bool = False) -> dict:
    return {'outcome': outcome, 'sim_s': sim_s, 'drop': drop}


def test_goal_summary_counts_first_tries_and_retries_apart():
    goals = [[_attempt('succeeded', 20.0, drop=True)],
             [_attempt('failed', 12.0, drop=True), _attempt('succeeded', 30.0)],
             [_attempt('failed', 5.0, drop=True), _attempt('timed out', 60.0)],
             [_attempt('succeeded', 40.0)]]
    s = goal_summary(goals)
    assert (s['goals'], s['first_try'], s['with_retry'], s['retried'], s['met_drop']) == (4, 2, 3, 2, 3)
    # a retried goal's time includes the failed attempt: what the mission waited for it
    assert s['goal_s_median'] == 40.0 and s['goal_s_max'] == 42.0


def test_goal_summary_of_no_reached_goal_has_no_times():
    s = goal_summary([[_attempt('canceled', 3.0)]])
    assert s['with_retry'] == 0 and math.isnan(s['goal_s_median'])


def test_memory_growth_is_measured_from_the_warm_up_not_the_start():
    growth = memory_growth({'1 gzserver': [100_000, 150_000, 156_000], '2 amcl': [80_000, 90_000, 90_000]})
    assert growth['1 gzserver'] == pytest.approx(0.04)
    assert growth['2 amcl'] == 0.0


def test_memory_growth_skips_processes_not_sampled_every_time():
    assert memory_growth({'7 zros node list': [30_000, 31_000], '8 router': [50_000, 0, 60_000]}) == {}


def test_missing_sequence_counts_holes_not_repeats():
    assert missing_sequence([1, 2, 3, 4]) == 0
    assert missing_sequence([5, 6, 8, 9, 12]) == 3
    assert missing_sequence([1, 2, 2, 3]) == 0
    assert missing_sequence([]) == 0


def test_link_goals_are_seeded_free_and_chained_from_the_spawn_pose():
    first, again = list(link_goals(3, seed=4)), list(link_goals(3, seed=4))
    assert first == again
    assert list(link_goals(3, seed=5)) != first
    for (x, y, yaw), ideal in first:
        assert -2.5 < x < 2.5 and -2.5 < y < 2.5 and -math.pi <= yaw <= math.pi
        assert ideal > 0.0
