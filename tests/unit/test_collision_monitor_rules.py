"""Nav2 Jazzy's collision monitor rules where they are easy to get subtly wrong.

The approach zone's clock: time reads 0 after the first simulated step and the simulation runs to
`time_before_collision` inclusive, so an obstacle the footprint would reach on the next step stops
the robot. A limit zone scales the whole command by one ratio (the curvature stays)."""
from __future__ import annotations

import numpy as np
import pytest

from zros.navigation.collision_monitor import Zone, decide

SPEED = 0.2          # [m/s]
STEP = 0.1           # [s]
RADIUS = 0.1         # [m] a round footprint


def _zone() -> Zone:
    return Zone('Footprint', 'approach', radius=RADIUS, min_points=6, time_before_collision=1.2,
                simulation_time_step=STEP)


def _cluster_entered_on_step(k: int) -> np.ndarray:
    """Six points straight ahead that the footprint, driven at SPEED, first holds after step k."""
    x = RADIUS + SPEED * STEP * (k - 0.5)
    return np.column_stack([np.full(6, x), np.linspace(-0.002, 0.002, 6)])


@pytest.mark.parametrize('k, ratio', [(1, 0.0), (2, 1 / 12), (6, 5 / 12), (12, 11 / 12)])
def test_the_command_is_scaled_by_the_time_before_the_step_that_touches(k, ratio):
    decision = decide([_zone()], _cluster_entered_on_step(k), np.array([SPEED, 0.0, 0.0]))
    assert decision.action == 'approach'
    assert decision.velocity[0] == pytest.approx(SPEED * ratio)


def test_an_obstacle_next_step_stops_the_robot_and_one_beyond_the_horizon_is_ignored():
    assert _zone().collision_time(_cluster_entered_on_step(1), np.array([SPEED, 0.0, 0.0])) == 0.0
    beyond = decide([_zone()], _cluster_entered_on_step(14), np.array([SPEED, 0.0, 0.0]))
    assert beyond.action == 'do_nothing' and beyond.velocity[0] == SPEED


def test_touching_on_the_horizon_itself_leaves_the_command_as_it_is():
    # reached after 13 steps: Nav2's clock reads 1.2 s = time_before_collision, a ratio of 1
    assert _zone().collision_time(_cluster_entered_on_step(13), np.array([SPEED, 0.0, 0.0])) == pytest.approx(1.2)
    assert decide([_zone()], _cluster_entered_on_step(13), np.array([SPEED, 0.0, 0.0])).action == 'do_nothing'


def test_a_limit_keeps_the_curvature_of_the_command():
    limit = Zone('Limit', 'limit', radius=1.0, min_points=1, linear_limit=0.1, angular_limit=0.2)
    near = np.array([[0.5, 0.0]])
    arc = np.array([0.4, 0.0, 0.5])
    limited = decide([limit], near, arc).velocity
    assert limited == pytest.approx([0.1, 0.0, 0.125])           # the linear limit binds: ratio 0.25
    assert limited[2] / limited[0] == pytest.approx(arc[2] / arc[0])
    spin = decide([limit], near, np.array([0.05, 0.0, 1.0])).velocity
    assert spin == pytest.approx([0.01, 0.0, 0.2])               # the angular limit binds: ratio 0.2

