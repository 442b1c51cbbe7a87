"""Navigation across a bad link that drops (issue 36): the laptop's Nav2 while the robot is gone.

The split TurtleBot3 stack of benchmarks/link.py (robot: gzserver and robot_state_publisher, a
client of the laptop's router through the shaper; laptop: map_server + AMCL and Nav2's servers)
and its mission script, BasicNavigator on the laptop, driving three seeded goals while the link
drops twice for 5 s, once holding the connection (Wi-Fi) and once resetting it.

What Nav2 does then, with the robot's simulated clock: the laptop's clock stops with /clock, so
the controller's loop, the progress checker and the navigator's replanning wait with it; the
goal pauses and carries on when the link returns. Whatever happens, a goal ends as Nav2 says
(succeeded or failed with an error code: the mission never has to give up on a hung one), no
process restarts, nothing collides, and a goal sent after the link returned succeeds.
"""
from __future__ import annotations

import json
import sys

import pytest

from benchmarks.link import _env, _start_stack
from tools.link_netns import Topology, unavailable_reason

from .conftest import REPO

LINK_BENCHMARK = REPO / 'benchmarks' / 'link.py'

pytestmark = pytest.mark.timeout(480)


def test_goals_pause_through_drop_outs_and_a_new_goal_succeeds_after(tmp_path):
    reason = unavailable_reason()
    if reason:
        pytest.skip(reason)
    sock = str(tmp_path / 'link.sock')
    with Topology(tmp_path) as topo:
        try:
            _start_stack(topo, sock, view=False)
        except SystemExit as exc:
            pytest.fail(f'{exc}; logs in {tmp_path}')
        stack = list(topo._procs)
        config = tmp_path / 'mission.json'
        out = tmp_path / 'mission-out.json'
        # the first drop-out 10 s into the first goal (about 20 s long), the second 10 s later
        config.write_text(json.dumps({'out': str(out), 'sock': sock, 'goals': 3, 'seed': 1, 'seconds': 400,
                                      'drop': 5.0, 'period': 10.0, 'max_drops': 2, 'modes': ['hold', 'reset']}))
        mission = topo.spawn(topo.laptop, [sys.executable, LINK_BENCHMARK, '--mission', config], 'mission', _env(), REPO)
        mission.wait(timeout=420)
        log = mission.log.read_text(errors='replace')
        assert out.exists(), f'the mission did not finish:\n{log[-3000:]}'
        result = json.loads(out.read_text())
        for proc in stack:
            assert proc.poll() is None, f'{proc.args[-3:]} exited: see {proc.log}'
    drops, goals = result['drops'], result['goals']
    assert len(drops) == 2, result
    attempts = [a for g in goals for a in g['attempts']]
    assert all(a['outcome'] in ('succeeded', 'failed') for a in attempts), f'a goal hung or was canceled: {goals}'
    assert any(a['drop'] for a in attempts), f'no goal was running when the link dropped: {result}'
    assert all(g['attempts'][-1]['outcome'] == 'succeeded' for g in goals), goals
    last = goals[-1]['attempts'][0]
    assert last['wall'][0] > drops[-1][1] and last['outcome'] == 'succeeded', \
        f'the goal sent after the link returned: {last}'
    assert result['collisions_end'] == result['collisions_start'], result
