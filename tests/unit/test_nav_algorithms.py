"""The navigation algorithms without Zenoh: costmap layers, planner, Regulated Pure Pursuit and
the checkers, and the three together driving zros.sim's robot."""
from __future__ import annotations

import math

import numpy as np
import pytest

from zros.navigation.controller import (FAILED_TO_MAKE_PROGRESS, NO_VALID_CONTROL, CollisionAhead, FollowError,
                                        GoalChecker, PathFollower, ProgressChecker, RegulatedPurePursuit, RPPParams,
                                        curvature_constraint, late_loop_scale)
from zros.navigation.costmap import (FREE_SPACE, INSCRIBED_INFLATED_OBSTACLE, LETHAL_OBSTACLE, NO_INFORMATION,
                                     CostmapParams, LayeredCostmap, footprint_from_radius, inflate, static_costs,
                                     to_occupancy)
from zros.navigation.planner import (GOAL_OCCUPIED, GOAL_OUTSIDE_MAP, NO_VALID_PATH, START_OCCUPIED, GridPlanner,
                                     PlanningError)


def _room(size: int = 60, resolution: float = 0.05) -> np.ndarray:
    """A walled square room (OccupancyGrid values) with a wall across the middle and a gap."""
    occ = np.zeros((size, size), np.int8)
    occ[0, :] = occ[-1, :] = occ[:, 0] = occ[:, -1] = 100
    occ[:, size // 2] = 100
    occ[size - 12:size - 4, size // 2] = 0      # the gap, near the top
    return occ


def _costmap(occ: np.ndarray, **kw) -> LayeredCostmap:
    cm = LayeredCostmap(CostmapParams(inflation_radius=0.55, cost_scaling_factor=3.0, **kw))
    cm.set_static_map(occ, 0.05, (0.0, 0.0))
    cm.update()
    return cm


def test_static_layer_translation_and_published_values():
    occ = np.array([[-1, 0, 50, 100]], np.int8)
    assert static_costs(occ).tolist() == [[NO_INFORMATION, FREE_SPACE, FREE_SPACE, LETHAL_OBSTACLE]]
    assert static_costs(occ, track_unknown_space=False)[0, 0] == FREE_SPACE
    assert to_occupancy(np.array([0, 253, 254, 255, 1, 252], np.uint8)).tolist() == [0, 99, 100, -1, 1, 98]


def test_inflation_follows_nav2s_exponential():
    costs = np.zeros((41, 41), np.uint8)
    costs[20, 20] = LETHAL_OBSTACLE
    out = inflate(costs, 0.05, inscribed_radius=0.1, inflation_radius=0.55, cost_scaling_factor=3.0)
    assert out[20, 20] == LETHAL_OBSTACLE
    assert out[20, 22] == INSCRIBED_INFLATED_OBSTACLE                       # 0.10 m
    assert out[20, 26] == int(252 * math.exp(-3.0 * (0.30 - 0.1)))         # 0.30 m: 138, the reference's example
    assert out[20, 32] == 0                                                 # 0.60 m: beyond the radius
    unknown = np.full((5, 5), NO_INFORMATION, np.uint8)
    unknown[2, 2] = LETHAL_OBSTACLE
    kept = inflate(unknown, 0.05, inscribed_radius=0.06, inflation_radius=0.5, cost_scaling_factor=3.0)
    assert kept[2, 3] == INSCRIBED_INFLATED_OBSTACLE and kept[2, 4] == NO_INFORMATION


def test_obstacle_layer_marks_hits_and_clears_along_beams():
    cm = LayeredCostmap(CostmapParams(rolling_window=True, width=4.0, height=4.0, use_static_layer=False,
                                      track_unknown_space=True, use_inflation_layer=False))
    cm.move_to(0.0, 0.0)
    angles = np.array([0.0, math.pi / 2])
    cm.add_scan((0.0, 0.0), angles, np.array([1.0, np.inf]), 0.12, 3.5)
    master = cm.update()
    assert cm.cost_at(np.array([[1.01, 0.0]]))[0] == LETHAL_OBSTACLE
    assert cm.cost_at(np.array([[0.5, 0.0], [0.0, 1.5]])).tolist() == [FREE_SPACE, FREE_SPACE]
    assert cm.cost_at(np.array([[-1.0, -1.0]]))[0] == NO_INFORMATION
    # The obstacle moved away: the next scan clears it.
    cm.add_scan((0.0, 0.0), angles, np.array([1.775, np.inf]), 0.12, 3.5)
    cm.update()
    assert cm.cost_at(np.array([[1.01, 0.0]]))[0] == FREE_SPACE
    # The window follows the robot and keeps what stays inside it.
    cm.move_to(0.5, 0.0)
    cm.update()
    assert cm.cost_at(np.array([[1.775, 0.0]]))[0] == LETHAL_OBSTACLE
    assert master.shape == (80, 80)


def test_planner_goes_through_the_gap_and_keeps_clear():
    cm = _costmap(_room())
    planner = GridPlanner(cm)
    path = planner.plan((0.6, 0.6), (2.4, 0.6))
    assert tuple(path[0]) == (0.6, 0.6) and tuple(path[-1]) == (2.4, 0.6)
    assert path[:, 1].max() > 2.2                     # up to the gap (y 2.4..2.8) and back down
    assert (cm.cost_at(path) < INSCRIBED_INFLATED_OBSTACLE).all()
    steps = np.linalg.norm(np.diff(path, axis=0), axis=1)
    assert steps.max() < 0.1


def test_planner_error_codes_and_tolerance():
    occ = _room()
    occ[:, 30] = 100                                  # close the gap: the right half is unreachable
    planner = GridPlanner(_costmap(occ))
    cases = {(1.5, 0.6): GOAL_OCCUPIED, (5.0, 0.6): GOAL_OUTSIDE_MAP, (2.4, 0.6): NO_VALID_PATH}
    for goal, code in cases.items():
        with pytest.raises(PlanningError) as err:
            planner.plan((0.6, 0.6), goal)
        assert err.value.code == code, goal
    with pytest.raises(PlanningError) as err:
        planner.plan((1.5, 1.0), (0.6, 0.6))
    assert err.value.code == START_OCCUPIED
    # A goal in the inflated zone (not lethal) is moved to the nearest free cell within tolerance.
    path = planner.plan((0.6, 0.6), (1.43, 0.6))
    assert 1.2 < path[-1][0] < 1.43


def test_regulations_and_rotate_to_heading():
    assert curvature_constraint(0.5, 1 / 0.45, 0.9) == pytest.approx(0.25)
    assert curvature_constraint(0.5, 1 / 2.0, 0.9) == 0.5
    rpp = RegulatedPurePursuit(RPPParams(desired_linear_vel=0.22, max_angular_vel=2.0))
    path = np.stack([np.linspace(0, 2, 41), np.zeros(41)], axis=1)
    v, w = rpp.compute((0.0, 0.2, 0.0), 0.0, path, 0.0, xy_goal_tolerance=0.25)
    assert 0 < v <= 0.22 and w < 0                    # the path is to the right: turn right
    v, w = rpp.compute((0.0, 0.0, math.pi), 0.0, path, 0.0, xy_goal_tolerance=0.25)
    assert v == 0 and w != 0                          # facing away: rotate in place first


def test_checkers_and_collision_ahead():
    progress = ProgressChecker(0.5, 10.0)
    assert progress.check(0, 0, 0.0) and progress.check(0.1, 0, 9.0) and not progress.check(0.2, 0, 10.5)
    goal = GoalChecker(0.25, 0.25)
    assert not goal.is_goal_reached((0.2, 0, 1.0), (0, 0, 0))   # near, heading off
    assert not goal.is_goal_reached((0.3, 0, 1.0), (0, 0, 0))
    assert goal.is_goal_reached((0.3, 0, 0.1), (0, 0, 0))       # stateful: position already reached
    follower = PathFollower(RegulatedPurePursuit(RPPParams()), GoalChecker(), ProgressChecker(0.5, 1.0))
    follower.set_path(np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]]), 0.0)
    follower.step((0.0, 0.0, 0.0), 0.0, 0.0)
    with pytest.raises(FollowError) as err:
        follower.step((0.0, 0.0, 0.0), 0.0, 2.0)
    assert err.value.code == FAILED_TO_MAKE_PROGRESS
    follower.set_path(np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]]), 0.0)
    wall = lambda pts: np.where(np.asarray(pts)[:, 0] > 0.3, LETHAL_OBSTACLE, FREE_SPACE).astype(np.uint8)  # noqa: E731
    with pytest.raises(FollowError) as err:
        follower.step((0.0, 0.0, 0.0), 0.0, 0.0, wall)
    assert err.value.code == NO_VALID_CONTROL


def test_failure_tolerance_stops_the_robot_and_retries_before_failing():
    """controller_server's failure_tolerance: a collision ahead stops the robot for as long as
    the tolerance allows; the goal fails only when the controller has failed for longer."""
    wall = lambda pts: np.where(np.asarray(pts)[:, 0] > 0.3, LETHAL_OBSTACLE, FREE_SPACE).astype(np.uint8)  # noqa: E731
    free = lambda pts: np.zeros(len(pts), np.uint8)  # noqa: E731
    follower = PathFollower(RegulatedPurePursuit(RPPParams()), GoalChecker(), ProgressChecker(),
                            failure_tolerance=0.3)
    follower.set_path(np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]]), 0.0)
    assert follower.step((0.0, 0.0, 0.0), 0.0, 0.0, wall) == (0.0, 0.0)
    assert follower.step((0.0, 0.0, 0.0), 0.0, 0.2, wall) == (0.0, 0.0)
    assert follower.step((0.0, 0.0, 0.0), 0.0, 0.3, free)[0] > 0.0      # the way cleared: driving again
    assert follower.step((0.0, 0.0, 0.0), 0.0, 0.4, wall) == (0.0, 0.0)   # the patience starts over
    with pytest.raises(FollowError) as err:
        follower.step((0.0, 0.0, 0.0), 0.0, 0.8, wall)
    assert err.value.code == NO_VALID_CONTROL and 'patience' in str(err.value)
    never = PathFollower(RegulatedPurePursuit(RPPParams()), GoalChecker(), ProgressChecker(0.5, 100.0),
                         failure_tolerance=-1.0)
    never.set_path(np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]]), 0.0)
    assert never.step((0.0, 0.0, 0.0), 0.0, 0.0, wall) == never.step((0.0, 0.0, 0.0), 0.0, 50.0, wall) == (0.0, 0.0)


def test_a_late_control_step_slows_the_command():
    """A loop that runs late holds each command longer: the speed is cut so that the distance per
    command stays what it was meant to be, down to a floor that still makes progress."""
    assert late_loop_scale(0.1, 0.1) == 1.0 and late_loop_scale(0.05, 0.1) == 1.0
    assert late_loop_scale(0.2, 0.1) == pytest.approx(0.5)
    assert late_loop_scale(10.0, 0.1) == 0.25
    follower = PathFollower(RegulatedPurePursuit(RPPParams(desired_linear_vel=0.2)), GoalChecker(),
                            ProgressChecker())
    follower.set_path(np.array([[0.0, 0.0], [2.0, 0.0], [4.0, 0.0]]), 0.0)
    on_time = follower.step((0.0, 0.0, 0.0), 0.2, 0.0)[0]
    assert follower.step((0.0, 0.0, 0.0), 0.2, 0.1)[0] == pytest.approx(on_time)   # on time: unchanged
    assert follower.step((0.0, 0.0, 0.0), 0.2, 0.4)[0] == pytest.approx(on_time / 3)   # 0.3 s late: a third


def _block(x0: float, x1: float, y0: float, y1: float):
    """cost_at for a lethal rectangle in free space."""
    def cost_at(points):
        pts = np.asarray(points)
        inside = (pts[:, 0] >= x0) & (pts[:, 0] <= x1) & (pts[:, 1] >= y0) & (pts[:, 1] <= y1)
        return np.where(inside, LETHAL_OBSTACLE, FREE_SPACE).astype(np.uint8)
    return cost_at


def test_a_blocked_arc_falls_back_to_the_near_carrot_then_to_turning_in_place():
    """In a doorway the arc to a far carrot cuts the jamb where the path itself is clear: the
    controller follows the carrot at min_lookahead_dist instead; when that arc is blocked too it
    turns in place towards it; facing it and still blocked is a real collision ahead."""
    controller = RegulatedPurePursuit(RPPParams(lookahead_dist=0.5, min_lookahead_dist=0.3))
    bend = np.array([[0.0, 0.0], [0.1, 0.0], [0.2, 0.0], [0.3, 0.0], [0.38, 0.13], [0.45, 0.26], [0.6, 0.5]])
    jamb = _block(0.2, 0.32, 0.06, 0.3)            # the far carrot's arc bulges into it, the path does not
    v, w = controller.compute((0.0, 0.0, 0.0), 0.0, bend, 0.0, xy_goal_tolerance=0.25, cost_at=jamb)
    assert v > 0.0 and abs(w) < 1e-6                # the near carrot (0.3, 0) is straight ahead
    line = np.column_stack([np.linspace(0.0, 2.0, 41), np.zeros(41)])
    ahead = _block(0.1, 0.3, 0.03, 0.3)            # in front of a robot turned 0.4 rad off the path
    v, w = controller.compute((0.0, 0.0, 0.4), 0.0, line, 0.0, xy_goal_tolerance=0.25, cost_at=ahead)
    assert v == 0.0 and w < 0.0                      # turning back towards the path
    with pytest.raises(CollisionAhead):
        controller.compute((0.0, 0.0, 0.0), 0.0, line, 0.0, xy_goal_tolerance=0.25, cost_at=_block(0.1, 0.3, -0.3, 0.3))
    no_turning = RegulatedPurePursuit(RPPParams(lookahead_dist=0.5, min_lookahead_dist=0.3, use_rotate_to_heading=False))
    with pytest.raises(CollisionAhead):
        no_turning.compute((0.0, 0.0, 0.4), 0.0, line, 0.0, xy_goal_tolerance=0.25, cost_at=ahead)


def test_once_at_the_goal_position_only_the_heading_is_turned_to():
    """Localisation noise that puts the robot just outside xy_goal_tolerance again must not turn
    it back towards the goal point (it would swing between the two headings for seconds)."""
    follower = PathFollower(RegulatedPurePursuit(RPPParams()), GoalChecker(), ProgressChecker())
    follower.set_path(np.array([[0.0, 0.0], [0.5, 0.0], [1.0, 0.0]]), math.pi / 2)
    assert follower.step((0.76, 0.0, 0.0), 0.0, 0.0)[0] == 0.0          # within 0.25 m: turning
    v, w = follower.step((0.74, 0.0, 0.0), 0.0, 0.1)                     # 0.26 m out, goal point ahead
    assert v == 0.0 and w > 0.0                                          # still turning to +90 deg
    assert follower.step((0.74, 0.0, math.pi / 2), 0.0, 0.2) is None


def test_plan_and_follow_in_the_simulator_without_collisions():
    from zros.sim import Simulation, parse_world, rasterize
    world = parse_world("""
name: room
spawn: {x: -1.0, y: -1.0, yaw: 0.0}
obstacles:
- ring: {center: [0, 0], sides: 4, inner_circumradius: 2.55, outer_circumradius: 2.83}
- box: {center: [0.3, 0.0], size: [0.4, 1.6], yaw: 0.0}
""")
    raster = rasterize(world, 0.05)
    cm = LayeredCostmap(CostmapParams(inflation_radius=0.55, cost_scaling_factor=3.0))
    cm.set_static_map(raster.occupancy_data().reshape(raster.cells.shape), 0.05, tuple(raster.origin))
    cm.update()
    planner = GridPlanner(cm)
    sim = Simulation(world, seed=3)
    robot = sim.add_robot('burger')
    follower = PathFollower(RegulatedPurePursuit(RPPParams(desired_linear_vel=0.22, max_angular_vel=2.0)),
                            GoalChecker(), ProgressChecker())
    for gx, gy, gyaw in [(1.4, 0.8, 1.57), (-1.0, 1.2, 3.14)]:
        pose = robot.pose
        follower.set_path(planner.plan((pose.x, pose.y), (gx, gy)), gyaw)
        while (cmd := follower.step((robot.pose.x, robot.pose.y, robot.pose.yaw), 0.0, sim.time, cm.cost_at)):
            robot.command(*cmd)
            sim.step(0.1)
            assert sim.time < 200
        robot.command(0.0, 0.0)
        assert math.hypot(robot.pose.x - gx, robot.pose.y - gy) < 0.25
    assert robot.collisions == 0


def test_frontiers_reachable_grouped_sorted_and_blacklisted():
    from zros.navigation.frontiers import Blacklist, find_frontiers
    occ = np.full((40, 60), -1, np.int8)
    occ[5:35, 5:30] = 0                         # a known room, open to the unknown on three sides
    occ[5:35, 5] = 100                          # its left wall: nothing to explore there
    occ[5:35, 45:50] = 0                        # known free space the robot cannot reach
    frontiers = find_frontiers(occ, 0.05, (0.0, 0.0), (0.5, 1.0), min_frontier_size=0.5)
    assert len(frontiers) == 1                  # top, right and bottom edges touch: one 8-connected frontier
    f = frontiers[0]
    assert f.size == 24 + 30 + 24               # the unknown cells 4-adjacent to the free ones, on three sides
    assert (f.points[:, 0] < 1.6).all()          # none from the unreachable patch (x 2.25..2.5)
    assert f.min_distance == pytest.approx(np.hypot(f.middle[0] - 0.5, f.middle[1] - 1.0))
    occ[35, 5:30] = 100                         # close the bottom and top: the right edge is left
    occ[4, 5:30] = 100
    right = find_frontiers(occ, 0.05, (0.0, 0.0), (0.5, 1.0), min_frontier_size=0.5)
    assert len(right) == 1 and right[0].size == 30 and right[0].centroid[0] == pytest.approx(1.525)
    assert find_frontiers(occ, 0.05, (0.0, 0.0), (0.5, 1.0), min_frontier_size=2.0) == []
    assert find_frontiers(np.full((40, 60), -1, np.int8), 0.05, (0.0, 0.0), (0.5, 1.0)) is None   # no scan yet
    blacklist = Blacklist(0.05)
    blacklist.add(right[0].centroid)
    assert blacklist.contains((right[0].centroid[0] + 0.2, right[0].centroid[1])) and not blacklist.contains((0, 0))


# -- assisted teleop ------------------------------------------------------------------------------
def test_assisted_teleop_projects_the_command_and_slows_before_a_collision():
    from zros.navigation.assisted_teleop import collision_scale, projected_poses
    times, poses = projected_poses((1.0, 2.0, np.pi / 2), (0.5, 0.0, 0.0), 0.1, 1.0)
    assert np.allclose(times, np.arange(1, 10) * 0.1)            # Nav2's steps: t < projection_time
    assert np.allclose(poses[:, 0], 1.0) and np.allclose(poses[-1, 1], 2.0 + 0.45)
    _, turning = projected_poses((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), 0.1, 1.0)
    assert np.allclose(turning[:, :2], 0.0) and np.isclose(turning[-1, 2], 0.9)
    clear = np.zeros(9, bool)
    assert collision_scale(times, clear, 1.0) == 1.0
    at_once = clear.copy()
    at_once[0] = True
    assert collision_scale(times, at_once, 1.0) == 0.0
    later = clear.copy()
    later[4:] = True                                               # first collision at t = 0.5 s
    assert np.isclose(collision_scale(times, later, 1.0), 0.5)


def test_clearing_a_square_around_or_outside_a_point_forgets_only_those_marks():
    costmap = LayeredCostmap(CostmapParams(resolution=0.1, width=4.0, height=4.0, rolling_window=True,
                                           use_static_layer=False, use_inflation_layer=False))
    costmap.move_to(0.0, 0.0)
    angles = np.linspace(-np.pi, np.pi, 360, endpoint=False)
    costmap.add_scan((0.0, 0.0), angles, np.where(np.abs(angles) < 0.2, 0.55, 1.55), 0.1, 3.5)
    marks = lambda: np.argwhere(costmap._obstacles == LETHAL_OBSTACLE)   # noqa: E731
    assert len(marks()) > 0
    near = np.column_stack(costmap.geometry.cell_centre(marks()[:, 0], marks()[:, 1]))
    assert (np.hypot(*near.T) < 1.0).any() and (np.hypot(*near.T) > 1.0).any()
    costmap.clear_square((0.0, 0.0), 2.0)                            # around: the close marks go
    left = np.column_stack(costmap.geometry.cell_centre(marks()[:, 0], marks()[:, 1]))
    assert len(left) > 0 and (np.abs(left) > 1.0).any(axis=1).all()
    costmap.clear_square((0.0, 0.0), 2.0, outside=True)              # except: the rest goes
    assert len(marks()) == 0


def test_a_control_step_longer_than_its_period_is_reported_as_nav2_does():
    from zros.navigation.servers import missed_rate_message
    assert missed_rate_message(20.0, 0.04) is None               # 40 ms of a 50 ms period
    assert missed_rate_message(20.0, 0.05) is None               # exactly the period still fits
    assert missed_rate_message(20.0, 0.08) == ('Control loop missed its desired rate of 20.0000 Hz. '
                                               'Current loop rate is 12.5000 Hz.')


def test_a_new_path_waits_for_the_running_step():
    """controller_server sets a new goal's path on one thread while the preempted goal's loop may
    be in a step on another (issue 36: one such interleaving raised IndexError and aborted a goal).
    The new path waits until the step ends; the step finishes on the path it began with."""
    import threading
    setter: list[threading.Thread] = []

    class SetsAPathMidStep(ProgressChecker):
        def check(self, x, y, now):   # called inside step, before the path is read
            if not setter:
                turn_back = np.array([[0.0, 0.0], [-1.0, 0.0], [-2.0, 0.0]])
                setter.append(threading.Thread(target=follower.set_path, args=(turn_back, math.pi)))
                setter[0].start()
                setter[0].join(0.3)
                assert setter[0].is_alive(), 'set_path ran in the middle of a step'
            return super().check(x, y, now)

    follower = PathFollower(RegulatedPurePursuit(RPPParams()), GoalChecker(), SetsAPathMidStep())
    follower.set_path(np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]]), 0.0)
    v, w = follower.step((0.0, 0.0, 0.0), 0.0, 0.0)
    assert v > 0.0 and abs(w) < 1e-6     # straight along the old path
    setter[0].join(5)
    assert not setter[0].is_alive() and follower.goal[:2] == (-2.0, 0.0)


def test_the_published_footprint_is_a_16_corner_circle_at_the_robot():
    corners = footprint_from_radius(0.105, (1.0, -2.0, 0.5))
    assert corners.shape == (16, 2)
    assert np.allclose(np.hypot(corners[:, 0] - 1.0, corners[:, 1] + 2.0), 0.105)
    assert np.allclose(corners[0], (1.0 + 0.105 * math.cos(0.5), -2.0 + 0.105 * math.sin(0.5)))
    assert np.allclose(footprint_from_radius(0.2).mean(axis=0), 0.0)
