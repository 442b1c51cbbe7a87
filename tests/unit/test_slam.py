"""zros.slam without Zenoh: each piece on a case whose answer is known, then the whole pipeline on
a short scripted drive in the simulator with biased odometry, against the world's exact raster."""
from __future__ import annotations

import math

import numpy as np
import pytest

from zros.slam import PoseGraphFileError, Slam, SlamParameters, scan_points
from zros.slam.geometry import compose, inverse, relative
from zros.slam.grid import LogOddsGrid, occupancy_from_scans
from zros.slam.match_grid import MatchGrid
from zros.slam.matcher import SearchWindow, match_scan
from zros.slam.pose_graph import PoseGraph
from zros.slam.serialization import read_pose_graph


def test_geometry_compose_inverse_relative():
    a, b = np.array([1.0, 2.0, 0.5]), np.array([-0.3, 0.7, -2.0])
    assert np.allclose(compose(a, inverse(a)), 0.0, atol=1e-12)
    assert np.allclose(compose(a, relative(a, b)), b)


def test_scan_points_follow_rep_117():
    ranges = [1.0, math.inf, math.nan, 0.05, 5.0, -math.inf]
    scan = scan_points(ranges, 0.0, math.pi / 2, range_min=0.12, range_max=3.5, sensor_pose=(-0.032, 0.0, 0.0),
                       missing_data_ray_length=3.0)
    assert np.allclose(scan.hits, [[0.968, 0.0]], atol=1e-6)            # only the 1 m return is a hit
    # +inf and a range beyond range_max: free for 3 m; NaN, -inf and too close tell nothing.
    assert np.allclose(scan.misses, [[-0.032, 3.0], [2.968, 0.0]], atol=1e-6)


def test_log_odds_grid_marks_the_hit_and_the_free_ray_and_removes_it_again():
    grid = LogOddsGrid(0.1)
    scan = scan_points([1.0], 0.0, 0.1, range_min=0.1, range_max=3.5)
    for _ in range(4):                      # one pass-through (p 0.4) is not yet 'free' (p < 0.196); four are
        grid.add_scan(np.zeros(3), scan)
    occupancy = grid.occupancy(margin=0)
    data, (ox, oy, _) = occupancy.data, occupancy.origin
    row = int(math.floor((0.0 - oy) / 0.1))
    assert data[row].tolist().count(100) == 1 and (data == 100).sum() == 1
    hit_col = data[row].tolist().index(100)
    assert ox + hit_col * 0.1 == pytest.approx(1.0)
    assert (data[row, :hit_col] == 0).all()                           # the ray before it is free
    for _ in range(4):
        grid.add_scan(np.zeros(3), scan, weight=-1.0)
    assert np.abs(grid.cells).max() < 1e-5                           # float32 rounding only


def test_pose_graph_closes_a_drifted_square():
    truth = np.array([[0, 0, 0], [2, 0, math.pi / 2], [2, 2, math.pi], [0, 2, -math.pi / 2], [0, 0, 0]], float)
    drift = np.array([0.05, 0.0, 0.03])                    # every odometry step is off by this
    graph = PoseGraph()
    info = np.diag([100.0, 100.0, 400.0])
    pose = truth[0]
    graph.add_node(pose)
    for i in range(1, 5):
        step = compose(relative(truth[i - 1], truth[i]), drift)
        pose = compose(pose, step)
        graph.add_node(pose)
        graph.add_edge(i - 1, i, step, info)
    before = np.hypot(*(graph.poses[4, :2] - truth[4, :2]))
    graph.add_edge(0, 4, np.zeros(3), np.diag([1e4, 1e4, 1e4]), robust=True)      # the loop closure
    result = graph.optimize()
    after = np.hypot(*(graph.poses[4, :2] - truth[4, :2]))
    assert before > 0.15 and after < 0.02 and result.final_cost < result.initial_cost


def _two_laps_with_a_snapped_link(*, robust_links: bool) -> float:
    """Two laps of a 1 m circle, 24 keyframes a lap, each second-lap keyframe closed onto its
    first-lap twin as it comes (the graph optimised after each, as Slam does); link 36 (mid
    second lap) is off by 0.05 rad, as a front end's snap in yaw. Returns the largest position error."""
    per_lap = 24
    angles = 2 * math.pi * np.arange(2 * per_lap) / per_lap
    truth = np.column_stack([np.cos(angles), np.sin(angles), angles + math.pi / 2])
    link, loop = np.diag([0.005 ** -2, 0.005 ** -2, 0.002 ** -2]), np.diag([0.01 ** -2, 0.01 ** -2, 0.005 ** -2])
    graph = PoseGraph()
    graph.add_node(truth[0])
    for k in range(1, len(truth)):
        step = relative(truth[k - 1], truth[k]) + (np.array([0.0, 0.0, 0.05]) if k == 36 else 0.0)
        graph.add_node(compose(graph.poses[k - 1], step))
        graph.add_edge(k - 1, k, step, link, robust=robust_links)
        if k >= per_lap:
            graph.add_edge(k - per_lap, k, np.zeros(3), loop, robust=True)
            graph.optimize()
    return float(np.hypot(*(graph.poses[:, :2] - truth[:, :2]).T).max())


def test_a_wrong_link_among_closures_that_agree_is_outvoted_when_links_are_robust():
    # The house's failure in small: a link that must be trusted spreads its error over the
    # chain (every keyframe a centimetre off); a robust one is outvoted and the rest stay put.
    assert _two_laps_with_a_snapped_link(robust_links=False) > 0.008
    assert _two_laps_with_a_snapped_link(robust_links=True) < 0.003


def test_matcher_finds_a_known_offset():
    # An L-shaped room corner and a pillar, as points every 2 cm.
    t = np.arange(0.0, 3.0, 0.02)
    reference = np.vstack([np.column_stack([t, np.zeros_like(t)]), np.column_stack([np.zeros_like(t), t]),
                           np.column_stack([1.5 + 0.15 * np.cos(t * 2), 1.5 + 0.15 * np.sin(t * 2)])])
    grid = MatchGrid(reference, 0.025, sigma=0.05)
    true_pose = np.array([0.8, 0.6, 0.3])
    points = relative(true_pose, np.column_stack([reference, np.zeros(len(reference))]))[:, :2]
    guess = true_pose + np.array([0.09, -0.07, 0.12])
    result = match_scan(grid, points, guess, SearchWindow(0.15, 0.2))
    assert np.hypot(*(result.pose[:2] - true_pose[:2])) < 0.01 and abs(result.pose[2] - true_pose[2]) < 0.01
    assert result.score > 0.9


def test_parameters_are_checked_by_name():
    with pytest.raises(ValueError, match='resolution must be > 0'):
        SlamParameters(resolution=0.0)
    with pytest.raises(ValueError, match='scan_buffer_size'):
        SlamParameters(scan_buffer_size=0)


def _drive(seconds: float, *, bias: float = 0.03, seed: int = 2):
    """A scripted drive in turtlebot3_world: scans every 0.2 s with odometry whose heading drifts
    `bias` rad per metre. Returns the Slam, the spawn pose, and the true, odometry and SLAM poses."""
    from zros.sim import LDS_01, Simulation, load_world
    world = load_world('turtlebot3_world')
    sim = Simulation(world, seed=seed)
    robot = sim.add_robot('burger', (world.spawn.x, world.spawn.y, world.spawn.yaw), odometry='encoder')
    slam = Slam(SlamParameters())
    spawn = np.array([world.spawn.x, world.spawn.y, world.spawn.yaw])
    truths, odoms, estimates = [], [], []
    travelled, last = 0.0, None
    odom_pose = np.zeros(3)
    for k in range(int(seconds / 0.2)):
        robot.command(0.2, 0.45 * math.sin(k * 0.05))
        sim.step(0.2)
        o = robot.odometry()
        raw = np.array([o.x, o.y, o.yaw])
        if last is not None:
            step = relative(last, raw)
            travelled = math.hypot(step[0], step[1])
            odom_pose = compose(odom_pose, step + np.array([0.0, 0.0, bias * travelled]))
        last = raw
        ranges = robot.scan()
        update = slam.process_scan(odom_pose, scan_points(ranges, LDS_01.angle_min, LDS_01.angle_increment,
                                                         range_min=LDS_01.range_min, range_max=LDS_01.range_max,
                                                         sensor_pose=(-0.032, 0.0, 0.0)))
        p = robot.pose
        truths.append(relative(spawn, np.array([p.x, p.y, p.yaw])))
        odoms.append(odom_pose.copy())
        estimates.append(update.pose)
    return slam, world, spawn, np.array(truths), np.array(odoms), np.array(estimates)


def test_a_short_drive_builds_a_map_whose_walls_match_the_truth(tmp_path):
    from zros.sim import rasterize
    from zros.sim.evaluation import trajectory_error
    slam, world, spawn, truths, odoms, estimates = _drive(20.0)
    slam_error = trajectory_error(estimates, truths)
    odom_error = trajectory_error(odoms, truths)
    assert slam_error.rmse < 0.03 and odom_error.final > 3 * slam_error.final, (slam_error, odom_error)
    assert slam.graph.edges and all(edge.robust for edge in slam.graph.edges)      # links too, not only closures
    # Each loop closure's information is its match's (zros.slam.loop_check): never tighter than
    # loop_sigma_*'s floor, and looser than it (the match's own covariance is added).
    p = slam.parameters
    floor = np.diag([p.loop_sigma_xy ** -2, p.loop_sigma_xy ** -2, p.loop_sigma_yaw ** -2])
    closures = [edge.information for edge in slam.graph.edges if edge.j - edge.i > 1]
    assert len(closures) == slam.loop_closures >= 1
    assert all(np.linalg.eigvalsh(floor - info).min() > -1e-6 * floor.max() for info in closures)
    assert not any(np.allclose(info, floor, rtol=1e-3) for info in closures)
    grid = slam.occupancy_map()
    truth = rasterize(world, 0.05)
    # Every occupied map cell within one cell of a true obstacle, nearly: no smear.
    from scipy import ndimage
    near = ndimage.binary_dilation(truth.cells, structure=np.ones((3, 3), dtype=bool))
    rows, cols = np.nonzero(grid.data == 100)
    local = np.column_stack([grid.origin[0] + (cols + 0.5) * 0.05, grid.origin[1] + (rows + 0.5) * 0.05])
    world_xy = compose(spawn, np.column_stack([local, np.zeros(len(local))]))[:, :2]
    cells = np.floor((world_xy - truth.origin) / 0.05).astype(int)
    assert len(cells) > 150
    assert near[cells[:, 1], cells[:, 0]].mean() > 0.97


def test_serialize_and_deserialize_the_pose_graph(tmp_path):
    slam, *_ = _drive(6.0)
    paths = slam.serialize(tmp_path / 'graph')
    assert [p.name for p in paths] == ['graph.posegraph', 'graph.data']     # slam_toolbox's two files
    again = Slam(SlamParameters())
    assert again.deserialize(tmp_path / 'graph.posegraph') == paths[0]       # with or without the suffix
    assert len(again.keyframes) == len(slam.keyframes)
    assert [len(e.measurement) for e in again.graph.edges] == [3] * len(slam.graph.edges)
    assert all(np.array_equal(a.scan.hits, b.scan.hits) for a, b in zip(again.keyframes, slam.keyframes))
    assert np.allclose(again.trajectory(), slam.trajectory())
    assert np.array_equal(again.occupancy_map().data, slam.occupancy_map().data)
    # merge_maps_kinematic draws a saved graph from scratch: the same map as the mapper's.
    saved = read_pose_graph(tmp_path / 'graph')
    drawn = occupancy_from_scans(saved.poses, saved.scans, 0.05)
    assert np.array_equal(drawn.data, slam.occupancy_map().data) and drawn.origin == slam.occupancy_map().origin
    (tmp_path / 'junk.posegraph').write_bytes(b'not a graph')
    with pytest.raises(PoseGraphFileError, match='junk.posegraph'):
        again.deserialize(tmp_path / 'junk.posegraph')
    (tmp_path / 'graph.data').unlink()
    with pytest.raises(PoseGraphFileError, match='graph.data'):            # the scans are in the second file
        again.deserialize(tmp_path / 'graph')
    assert len(again.keyframes) == len(slam.keyframes)                    # a failed load changes nothing


def test_localization_in_a_saved_map_finds_the_robot_and_keeps_the_map_fixed(tmp_path):
    from zros.sim import LDS_01, Simulation
    slam, world, spawn, *_ = _drive(20.0)
    slam.serialize(tmp_path / 'graph')
    start = np.array([0.5, -1.2, 1.2])                   # elsewhere in the arena (world frame)
    sim = Simulation(world, seed=5)
    robot = sim.add_robot('burger', tuple(start))
    localizer = Slam(SlamParameters())
    guess = relative(spawn, start) + np.array([0.15, -0.1, 0.1])       # the start pose given is off a little
    localizer.deserialize(tmp_path / 'graph', pose=tuple(guess), localize=True)
    nodes, first_map = len(localizer.keyframes), localizer.occupancy_map().data.copy()

    def step(k):
        robot.command(0.15, 0.4 * math.sin(k * 0.07))
        sim.step(0.2)
        o = robot.odometry()
        update = localizer.process_scan(np.array([o.x, o.y, o.yaw]), scan_points(
            robot.scan(), LDS_01.angle_min, LDS_01.angle_increment, range_min=LDS_01.range_min,
            range_max=LDS_01.range_max, sensor_pose=(-0.032, 0.0, 0.0)))
        p = robot.pose
        truth = relative(spawn, np.array([p.x, p.y, p.yaw]))
        return update, np.hypot(*(update.pose[:2] - truth[:2])), abs(update.pose[2] - truth[2])

    errors = [step(k) for k in range(40)]
    assert localizer.localizing and all(u.matched and not u.keyframe for u, _, _ in errors)
    assert max(e for _, e, _ in errors) < 0.04 and max(a for _, _, a in errors) < 0.02, errors
    assert len(localizer.keyframes) == nodes and np.array_equal(localizer.occupancy_map().data, first_map)
    assert 1 < len(localizer._buffer) <= SlamParameters().scan_buffer_size      # the rolling buffer
    # /initialpose: a new guess near the truth, and the next scan is matched there.
    p = robot.pose
    localizer.relocalize(relative(spawn, np.array([p.x, p.y, p.yaw])) + np.array([-0.12, 0.1, -0.08]))
    assert not localizer._buffer
    update, error, angle = step(40)
    assert update.matched and error < 0.04 and angle < 0.02


def _corridor(with_end_wall: bool) -> np.ndarray:
    """Points every 2 cm on the two walls of a 2 m wide corridor (and, if asked, a wall across it)."""
    t = np.arange(-4.0, 4.0, 0.02)
    walls = [np.column_stack([t, np.full_like(t, 1.0)]), np.column_stack([t, np.full_like(t, -1.0)])]
    if with_end_wall:
        s = np.arange(-1.0, 1.0, 0.02)
        walls.append(np.column_stack([np.full_like(s, 3.0), s]))
    return np.vstack(walls)


def test_a_corridor_leaves_the_direction_along_it_to_the_prediction():
    from zros.slam.matcher import keep_prediction_along, weak_directions
    for with_end_wall in (False, True):
        reference = _corridor(with_end_wall)
        grid = MatchGrid(reference, 0.025, sigma=0.05)
        true_pose = np.array([0.3, 0.1, 0.05])
        points = relative(true_pose, np.column_stack([reference, np.zeros(len(reference))]))[:, :2]
        points = points[np.hypot(points[:, 0], points[:, 1]) < 3.5]               # what the LDS-01 reaches
        predicted = true_pose + np.array([0.08, -0.06, 0.04])
        result = match_scan(grid, points, predicted, SearchWindow(0.15, 0.2))
        weak = weak_directions(result.information)
        pose = keep_prediction_along(result.pose, predicted, weak)
        assert abs(pose[1] - true_pose[1]) < 0.01 and abs(pose[2] - true_pose[2]) < 0.01    # across, and turned
        if with_end_wall:                       # the wall across it fixes the rest
            assert len(weak) == 0 and abs(pose[0] - true_pose[0]) < 0.01
        else:                                   # along it: odometry's x, whatever the search picked
            assert len(weak) == 1 and abs(abs(weak[0, 0]) - 1.0) < 0.05
            assert pose[0] == pytest.approx(predicted[0], abs=0.01)


def test_weak_directions_of_no_information_and_of_full_information():
    from zros.slam.matcher import weak_directions
    assert len(weak_directions(np.zeros((3, 3)))) == 2
    assert len(weak_directions(np.diag([100.0, 50.0, 1000.0]))) == 0
    # Information in x only through the yaw (a lever arm): marginalising the yaw leaves y weak.
    strong_x = np.array([[100.0, 0.0, 0.0], [0.0, 50.0, 50.0], [0.0, 50.0, 50.0]])
    weak = weak_directions(strong_x)
    assert len(weak) == 1 and abs(abs(weak[0, 1]) - 1.0) < 1e-9


def test_a_keyframe_comes_every_odometry_step_even_when_the_match_holds_the_robot_still():
    # The bighouse corridor's lock in small: the front end keeps the robot where the last keyframe
    # was (here: the same scan over and over), odometry says it moved. Counting the step in
    # odometry too (slam_toolbox counts only there) still makes keyframes, so the map grows.
    t = np.arange(0.0, 3.0, 0.02)
    room = np.vstack([np.column_stack([t - 1.0, np.full_like(t, -1.0)]), np.column_stack([np.full_like(t, -1.0), t - 1.0]),
                      np.column_stack([0.8 + 0.15 * np.cos(t * 2), 0.9 + 0.15 * np.sin(t * 2)])])
    from zros.slam.scan import ScanPoints
    scan = ScanPoints(np.zeros(2), room.astype(np.float32), np.zeros((0, 2), np.float32))
    slam = Slam(SlamParameters(do_loop_closing=False))
    updates = [slam.process_scan(np.array([0.05 * k, 0.0, 0.0]), scan) for k in range(9)]
    assert all(np.allclose(u.pose, 0.0, atol=0.01) for u in updates)              # the match holds it
    assert [k for k, u in enumerate(updates) if u.keyframe] == [0, 4, 8]           # 0.2 m of odometry each


def test_within_reach_keeps_the_points_some_scan_of_the_local_map_could_see():
    from zros.slam.scan import within_reach
    points = np.array([[0.0, 3.0], [3.4, 0.0], [3.6, 0.0], [-2.0, -2.0], [9.0, 9.0]])
    origins = np.array([[0.0, 0.0], [-1.0, 0.0]])
    assert within_reach(points, origins, np.array([3.5, 2.0])).tolist() == [True, True, False, True, False]
    assert within_reach(points, np.zeros((0, 2)), np.zeros(0)).tolist() == [False] * 5


def test_a_scan_reaching_past_the_local_map_is_not_pulled_back_onto_it():
    # A corridor with posts on its walls, mapped by keyframes every 0.2 m up to x = 0 with a
    # 3.5 m lidar; the robot is at x = 0.2 (or 0.3) and sees walls up to 0.2 m past the map's
    # end. Those points fit nowhere on it: with them the match is pulled back, without them not.
    from zros.slam.scan import within_reach
    t = np.arange(-8.0, 8.0, 0.02)
    stub = np.arange(0.0, 0.3, 0.02)
    world = np.vstack([np.column_stack([t, np.full_like(t, 1.0)]), np.column_stack([t, np.full_like(t, -1.0)])]
                      + [np.column_stack([np.full_like(stub, x), side * (1.0 - stub)])
                         for x, side in ((-2.9, 1), (-1.3, -1), (0.6, 1), (2.1, -1), (3.9, 1), (5.0, -1))])

    def seen_from(x: float) -> np.ndarray:
        return world[np.hypot(world[:, 0] - x, world[:, 1]) < 3.5]

    keyframes = np.arange(-1.8, 0.01, 0.2)
    grid = MatchGrid(np.vstack([seen_from(x) for x in keyframes]), 0.025, sigma=0.05)
    origins = np.column_stack([keyframes, np.zeros_like(keyframes)])
    for true_x in (0.2, 0.3):
        truth = np.array([true_x, 0.0, 0.0])
        points = seen_from(true_x) - truth[:2]
        predicted = truth + np.array([0.05, 0.0, 0.0])
        every = match_scan(grid, points, predicted, SearchWindow(0.15, 0.2))
        reachable = points[within_reach(points + predicted[:2], origins, np.full(len(keyframes), 3.5))]
        found = match_scan(grid, reachable, predicted, SearchWindow(0.15, 0.2))
        assert true_x - every.pose[0] > 0.01                   # pulled back towards the map's end
        assert abs(found.pose[0] - true_x) < 0.005 and abs(found.pose[1]) < 0.005


def test_a_direction_held_only_by_a_door_frame_is_weak_in_a_corridor_not_in_open_ground():
    from zros.slam.matcher import weak_directions
    # The bighouse's corridor: 15 points' worth along it, 100 across. The search's pick along it is
    # noise (centimetres a scan, mostly backwards), so the prediction is kept there.
    corridor = np.diag([15.0, 100.0, 300.0])
    weak = weak_directions(corridor)
    assert len(weak) == 1 and abs(abs(weak[0, 0]) - 1.0) < 1e-9
    # Open ground as weak one way but nearly as weak the other (turtlebot3_world between the
    # pillars): not a corridor, the match is used.
    assert len(weak_directions(np.diag([15.0, 40.0, 300.0]))) == 0
    # Plenty along it (a wall across the corridor): used, however much there is across.
    assert len(weak_directions(np.diag([30.0, 400.0, 300.0]))) == 0
    # Loop closures ask only for some information (their covariance handles the rest).
    assert len(weak_directions(corridor, anisotropy=0.0)) == 0
