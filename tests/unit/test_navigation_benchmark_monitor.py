"""benchmarks/navigation.py's collision monitor (`--collision-monitor`): nav2_bringup's zone,
judged on the robot's own scan, slows a command that would run into a wall and leaves the rest
alone, whatever the localisation believes."""
from __future__ import annotations

import numpy as np
import pytest

from benchmarks.navigation import LASER, monitor_decision, monitor_zones
from zros.sim import LDS_01


def _wall_ahead(distance: float) -> np.ndarray:
    """An LDS-01 scan [m] of a straight wall `distance` [m] ahead of the base frame's origin."""
    angles = LDS_01.angles()
    with np.errstate(divide='ignore'):
        ranges = (distance - LASER[0]) / np.cos(angles)
    ranges[(np.cos(angles) <= 0.0) | (ranges > LDS_01.range_max)] = np.inf
    return ranges


def test_the_zone_is_nav2_bringups_approach_zone_around_the_footprint():
    zones = monitor_zones(0.105)
    assert [(z.name, z.action_type) for z in zones] == [('FootprintApproach', 'approach')]
    assert zones[0].radius == 0.105
    assert zones[0].time_before_collision == pytest.approx(1.2)
    assert zones[0].min_points == 6


def test_driving_at_a_wall_is_slowed_and_stopped_at_it():
    zones = monitor_zones(0.105)
    near = monitor_decision(zones, _wall_ahead(0.3), (0.22, 0.0))
    assert near.action == 'approach'
    assert 0.0 <= near.velocity[0] < 0.22
    touching = monitor_decision(zones, _wall_ahead(0.1), (0.22, 0.0))
    assert touching.velocity[0] == pytest.approx(0.0)


def test_open_space_turns_and_driving_away_pass_unchanged():
    zones = monitor_zones(0.105)
    assert monitor_decision(zones, _wall_ahead(2.0), (0.22, 0.0)).action == 'do_nothing'
    assert monitor_decision(zones, _wall_ahead(0.3), (0.0, 1.0)).action == 'do_nothing'
    assert monitor_decision(zones, _wall_ahead(0.3), (-0.05, 0.0)).action == 'do_nothing'


def test_the_benchmark_counts_commands_slowed_and_stopped_but_not_standing_still():
    from benchmarks.navigation import Stack, exact_map
    from zros.sim import load_world
    world = load_world('turtlebot3_world')
    stack = Stack(world, exact_map(world), 1, truth_pose=True, collision_monitor=True)
    stack.loc.ranges = _wall_ahead(0.3)
    slowed = stack.monitored((0.22, 0.0))
    assert 0.0 < slowed[0] < 0.22
    assert stack.monitored((0.0, 0.0)) == (0.0, 0.0)          # nothing to slow: not counted
    stack.loc.ranges = _wall_ahead(0.1)
    assert stack.monitored((0.22, 0.0)) == (0.0, 0.0)
    assert (stack.monitor_acted, stack.monitor_stopped) == (2, 1)
