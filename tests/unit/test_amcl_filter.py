"""zros.amcl without Zenoh: motion models, the likelihood field, KLD resampling, recovery,
initialisation in free space, the estimate, and the whole filter localizing in the simulator."""
from __future__ import annotations

import math

import numpy as np
import pytest

from zros.amcl import (Amcl, AmclParameters, DifferentialMotionModel, LikelihoodFieldModel, MapGrid, OmniMotionModel,
                       ParticleFilter, create_laser_model, create_motion_model)
from zros.amcl.localizer import compose, inverse
from zros.amcl.particle_filter import kld_limit
from zros.amcl.sensor_models import LaserScanData, distance_field
from zros.rotations import angle_diff
from zros.sim import BURGER, LDS_01, Simulation, load_world, rasterize

LASER = (BURGER.lidar_mount[0], 0.0, 0.0)


def world_map(world, start) -> MapGrid:
    raster = rasterize(world, 0.05)
    grid = MapGrid(raster.occupancy_data(), resolution=0.05, origin=raster.origin, width=raster.width)
    return grid.reachable_from(*start)


@pytest.fixture(scope='module')
def tb3_world():
    world = load_world('turtlebot3_world')
    return world, world_map(world, (world.spawn.x, world.spawn.y))


def box_map(size: int = 40, resolution: float = 0.1) -> MapGrid:
    data = np.zeros((size, size), dtype=np.int8)
    data[0, :] = data[-1, :] = data[:, 0] = data[:, -1] = 100
    return MapGrid(data, resolution=resolution, origin=(0.0, 0.0))


def drive(model, particles, poses, rng):
    previous = poses[0]
    for pose in poses[1:]:
        delta = pose - previous
        delta[2] = angle_diff(pose[2], previous[2])
        model.odometry_update(particles, pose, delta, rng)
        previous = pose


# -- motion models ---------------------------------------------------------------------------------
@pytest.mark.parametrize('model_type', ['nav2_amcl::DifferentialMotionModel', 'differential',
                                        'nav2_amcl::OmniMotionModel', 'omnidirectional'])
def test_noise_free_motion_follows_the_odometry_from_any_start(model_type):
    model = create_motion_model(model_type, (0.0, 0.0, 0.0, 0.0, 0.0))
    t = np.linspace(0, 6, 60)
    odometry = np.column_stack([np.cos(t) * 2, np.sin(t), angle_diff(t * 0.7, 0.0)])
    start = np.array([[1.0, -2.0, 0.5], [0.0, 0.0, 3.0]])        # map poses of the first odometry pose
    particles = start.copy()
    drive(model, particles, odometry, np.random.default_rng(0))
    for s, p in zip(start, particles):
        expected = compose(compose(s, inverse(odometry[0])), odometry[-1])
        assert np.allclose(p[:2], expected[:2], atol=1e-9)
        assert abs(angle_diff(p[2], expected[2])) < 1e-9


def test_noise_grows_with_the_alphas_and_driving_backwards_is_not_a_half_turn():
    rng = np.random.default_rng(1)
    forward = np.array([[0.0, 0.0, 0.0], [0.3, 0.0, 0.0]])
    backward = np.array([[0.0, 0.0, 0.0], [-0.3, 0.0, 0.0]])
    spreads = []
    for alpha in (0.05, 0.2, 0.8):
        p = np.zeros((4000, 3))
        drive(DifferentialMotionModel(alpha, alpha, alpha, alpha), p, forward, rng)
        spreads.append(p.std(axis=0))
    assert spreads[0][0] < spreads[1][0] < spreads[2][0]
    assert spreads[0][2] < spreads[1][2] < spreads[2][2]
    p = np.zeros((4000, 3))
    drive(DifferentialMotionModel(0.2, 0.2, 0.2, 0.2), p, backward, rng)
    assert abs(p[:, 0].mean() + 0.3) < 0.01
    assert p[:, 2].std() < 0.3          # a half turn's noise would be ~sqrt(0.2) * pi


def test_the_sampled_motions_mean_is_the_odometrys_but_for_the_heading_noises_shortening():
    """Nav2's sample_motion_model_odometry is unbiased in each of its three parts; the mean
    position falls short of the odometry only by E[cos] of the heading noise, exp(-var / 2)."""
    rng = np.random.default_rng(11)
    start, end = np.array([0.5, -0.2, 0.3]), np.array([0.5 + 0.25 * math.cos(0.4), -0.2 + 0.25 * math.sin(0.4), 0.45])
    delta = end - start
    n = 400_000
    no_heading_noise = np.tile(start, (n, 1))
    DifferentialMotionModel(0.0, 0.0, 0.2, 0.2).odometry_update(no_heading_noise, end, delta, rng)
    error = no_heading_noise.mean(axis=0) - end
    assert np.abs(error[:2]).max() < 4 * no_heading_noise[:, 0].std() / math.sqrt(n)
    assert abs(error[2]) < 1e-9
    noisy = np.tile(start, (n, 1))
    DifferentialMotionModel(0.2, 0.2, 0.2, 0.2).odometry_update(noisy, end, delta, rng)
    rot1, trans = 0.1, 0.25
    shrink = math.exp(-(0.2 * rot1 ** 2 + 0.2 * trans ** 2) / 2.0)
    expected = start[:2] + trans * shrink * np.array([math.cos(start[2] + rot1), math.sin(start[2] + rot1)])
    assert np.abs(noisy[:, :2].mean(axis=0) - expected).max() < 4 * noisy[:, 0].std() / math.sqrt(n)
    assert abs(math.atan2(np.sin(noisy[:, 2]).mean(), np.cos(noisy[:, 2]).mean()) - end[2]) < 1e-3


def test_omni_strafe_noise_comes_from_alpha5():
    rng = np.random.default_rng(2)
    sideways = np.array([[0.0, 0.0, 0.0], [0.0, 0.4, 0.0]])
    quiet, noisy = np.zeros((3000, 3)), np.zeros((3000, 3))
    drive(OmniMotionModel(0.0, 0.0, 0.0, 0.0, 0.0), quiet, sideways, rng)
    drive(OmniMotionModel(0.0, 0.0, 0.0, 0.0, 0.5), noisy, sideways, rng)
    assert np.allclose(quiet[:, :2], [0.0, 0.4])
    assert noisy[:, 0].std() > 0.2 and abs(noisy[:, 1].mean() - 0.4) < 0.02


def test_unknown_model_names_are_refused_with_the_known_ones():
    with pytest.raises(ValueError, match='nav2_amcl::DifferentialMotionModel'):
        create_motion_model('tank', (0.2,) * 5)
    with pytest.raises(ValueError, match='likelihood_field'):
        create_laser_model('beam', box_map(), z_hit=0.5, z_rand=0.5, sigma_hit=0.2, max_dist=2.0, max_beams=60)


# -- the laser model --------------------------------------------------------------------------------
def test_distance_field_is_euclidean_and_capped():
    data = np.zeros((21, 21), dtype=np.int8)
    data[10, 10] = 100
    grid = MapGrid(data, resolution=0.1, origin=(0.0, 0.0))
    field = distance_field(grid, 0.5)
    assert field[10, 10] == 0.0
    assert field[10, 13] == pytest.approx(0.3)
    assert field[13, 14] == pytest.approx(0.5)          # 0.5 exactly (3-4-5)
    assert field[0, 0] == 0.5                          # capped
    assert (distance_field(MapGrid(np.zeros((3, 3)), resolution=0.1), 2.0) == 2.0).all()


@pytest.mark.parametrize('laser_model_type', ['likelihood_field', 'likelihood_field_prob'])
def test_the_true_pose_explains_the_scan_best(tb3_world, laser_model_type):
    world, grid = tb3_world
    sim = Simulation(world, seed=4)
    robot = sim.add_robot('burger')
    amcl = Amcl(AmclParameters(laser_model_type=laser_model_type), grid, seed=0)
    scan = amcl.prepare_scan(robot.scan(), LDS_01.angles(), LDS_01.range_min, LDS_01.range_max)
    p = robot.pose
    offsets = np.array([[0, 0, 0], [0.15, 0, 0], [0, -0.15, 0], [0, 0, 0.15], [0.5, 0.3, -0.4], [-0.3, 0.2, 1.0]])
    likelihood = amcl.laser_model.likelihood(np.array([p.x, p.y, p.yaw]) + offsets, scan, LASER)
    assert int(np.argmax(likelihood)) == 0
    assert likelihood[0] > 1.5 * likelihood[4:].max()


def test_beams_beyond_range_nan_and_too_close_are_not_used():
    amcl = Amcl(AmclParameters(max_beams=6), box_map(), seed=0)
    ranges = np.array([1.0, np.nan, -np.inf, np.inf, 0.05, 2.0])
    scan = amcl.prepare_scan(ranges, np.linspace(0, 2, 6), 0.12, 3.5)
    used, _ = amcl.laser_model.beams(scan)
    assert list(used) == [1.0, 2.0]
    empty = LaserScanData(np.full(6, np.nan), np.zeros(6), 3.5)
    assert (amcl.laser_model.likelihood(np.zeros((3, 3)), empty, LASER) == 1.0).all()


def test_beam_skipping_leaves_out_beams_the_map_does_not_explain():
    grid = box_map()
    model = create_laser_model('likelihood_field_prob', grid, z_hit=0.5, z_rand=0.5, sigma_hit=0.2, max_dist=2.0,
                               max_beams=8, do_beamskip=True, beam_skip_threshold=0.3)
    assert isinstance(model, LikelihoodFieldModel)
    particles = np.array([[2.0, 2.0, 0.0], [2.05, 2.0, 0.0]])
    bearings = np.linspace(0, 2 * np.pi, 8, endpoint=False)
    wall = np.full(8, 1.9)                      # every beam ends on the box's walls (cells 0 and 39)
    person = wall.copy()
    person[0] = 0.5                              # one beam ends on someone in the middle of the room
    with_person = model.likelihood(particles, LaserScanData(person, bearings, 3.5), (0.0, 0.0, 0.0))
    without = model.likelihood(particles, LaserScanData(wall, bearings, 3.5), (0.0, 0.0, 0.0))
    assert np.allclose(with_person / with_person[0], without / without[0])


def thick_wall_map(middle: int) -> MapGrid:
    """A room 2 m x 2 m at 0.05 m with a wall three cells thick at x = 1.0-1.15 m (columns 20-22),
    free on both sides; its middle column is `middle` (-1: unknown, as a lidar maps a wall; 100: solid)."""
    data = np.zeros((40, 40), dtype=np.int8)
    data[:, 20] = data[:, 22] = 100
    data[:, 21] = middle
    return MapGrid(data, resolution=0.05, origin=(0.0, 0.0))


@pytest.mark.parametrize('middle', [-1, 100])
def test_a_beam_that_came_out_through_a_wall_is_no_hit(middle):
    model = create_laser_model('likelihood_field_prob', thick_wall_map(middle), z_hit=0.5, z_rand=0.5,
                               sigma_hit=0.2, max_dist=2.0, max_beams=2)
    ranges, bearings = np.array([0.52]), np.array([0.0])           # one beam, straight along +x
    # From x = 0.5 the beam ends on the near face (x 1.02); 0.11 m closer on the far face (1.13),
    # 0.16 m closer one cell past it (1.18); 0.06 m closer inside the wall (1.08).
    particles = np.array([[0.5, 1.0, 0.0], [0.61, 1.0, 0.0], [0.66, 1.0, 0.0], [0.56, 1.0, 0.0]])
    distance = model.end_distances(particles, ranges, bearings, (0.0, 0.0, 0.0))[:, 0]
    assert distance[0] == 0.0
    assert distance[1] == distance[2] == 2.0                      # as if the beam had ended off the map
    assert distance[3] == pytest.approx(0.05 if middle < 0 else 0.0)    # still inside: the field's own score
    likelihood = model.likelihood(particles, LaserScanData(ranges, bearings, 3.5), (0.0, 0.0, 0.0))
    assert likelihood[0] > 2.0 * likelihood[1]                     # Nav2's field scores both as hits


def test_a_map_smaller_than_the_look_back_still_makes_a_laser_model():
    """The node checks its parameters on a 3 x 3 map; a look-back longer than the map must not
    turn into slices counted from the other end."""
    model = create_laser_model('likelihood_field_prob', MapGrid(np.zeros((3, 3)), resolution=1.0), z_hit=0.5,
                               z_rand=0.5, sigma_hit=0.2, max_dist=2.0, max_beams=60)
    assert model.likelihood(np.zeros((1, 3)), LaserScanData(np.array([1.0]), np.zeros(1), 3.5), LASER).shape == (1,)


def test_the_beams_used_are_nav2s_evenly_spaced_ones_that_returned():
    """Nav2 spaces max_beams over the whole scan and drops those out of range: with 30 of 360
    in range that leaves 5; a full scan uses every 6th."""
    model = create_laser_model('likelihood_field_prob', box_map(), z_hit=0.5, z_rand=0.5, sigma_hit=0.2,
                               max_dist=2.0, max_beams=60)
    bearings = np.radians(np.arange(360.0))
    ranges = np.full(360, np.inf)
    ranges[100:130] = 2.0
    used, used_bearings = model.beams(LaserScanData(ranges, bearings, 3.5))
    assert len(used) == 5 and np.array_equal(used_bearings, bearings[102:130:6])
    full = np.linspace(0.5, 3.0, 360)
    used, used_bearings = model.beams(LaserScanData(full, bearings, 3.5))
    assert np.array_equal(used_bearings, bearings[:-1:6]) and len(used) == 60


def test_a_beam_grazing_a_thin_wall_is_still_a_hit():
    data = np.full((40, 40), -1, dtype=np.int8)                   # unknown beyond a one-cell wall at row 20
    data[:20] = 0
    data[20] = 100
    model = create_laser_model('likelihood_field_prob', MapGrid(data, resolution=0.05, origin=(0.0, 0.0)),
                               z_hit=0.5, z_rand=0.5, sigma_hit=0.2, max_dist=2.0, max_beams=2)
    # From (0.1, 0.85) to (1.8, 1.02) on the wall's face, 5.7 deg off it: the look-back points stay
    # in the face's cells; from 1 cm higher the end point lies just behind the face.
    bearing = math.atan2(0.17, 1.7)
    particles = np.array([[0.1, 0.85, 0.0], [0.1, 0.86, 0.0]])
    distance = model.end_distances(particles, np.array([math.hypot(1.7, 0.17)]), np.array([bearing]),
                                   (0.0, 0.0, 0.0))
    assert distance[0, 0] == 0.0 and distance[1, 0] <= 0.05       # a hit, and a near one: never the maximum


def test_parameters_from_a_params_file_section_cast_and_ignore_other_names():
    parameters = AmclParameters.from_parameters({'alpha1': 1, 'max_beams': 30.0, 'do_beamskip': True,
                                                 'laser_model_type': 'likelihood_field_prob', 'use_sim_time': True})
    assert parameters.alpha1 == 1.0 and isinstance(parameters.alpha1, float)
    assert parameters.max_beams == 30 and isinstance(parameters.max_beams, int)
    assert parameters.do_beamskip and parameters.laser_model_type == 'likelihood_field_prob'
    assert parameters.alpha2 == AmclParameters().alpha2


# -- the particle filter ---------------------------------------------------------------------------------
def test_kld_limit_grows_with_the_occupied_bins_within_bounds():
    k = np.array([0, 1, 2, 10, 50, 200, 5000])
    limit = kld_limit(k, pf_err=0.05, pf_z=0.99, min_particles=100, max_particles=3000)
    assert limit[0] == limit[1] == 3000           # Nav2: one bin (or none) asks for the most
    assert limit[2] == 100 and limit[3] < limit[4] < limit[5] and limit[6] == 3000


def test_resampling_adapts_the_count_and_keeps_the_weights_proportions():
    pf = ParticleFilter(box_map(), min_particles=200, max_particles=4000, rng=np.random.default_rng(5))
    pf.init_uniform()
    assert len(pf) == 4000
    pf.resample()
    assert len(pf) == 4000                        # spread over the room: many bins
    pf.particles = np.array([[1.0, 1.0, 0.0], [3.0, 3.0, 1.0]])
    pf.weights = np.array([0.25, 0.75])
    pf.resample()
    share = np.mean(pf.particles[:, 0] == 3.0)
    assert 200 <= len(pf) < 1000 and abs(share - 0.75) < 0.01     # low variance: exact to one particle


def test_recovery_injects_random_particles_when_the_fit_drops():
    pf = ParticleFilter(box_map(), min_particles=500, max_particles=500, alpha_slow=0.001, alpha_fast=0.5,
                        rng=np.random.default_rng(6))
    pf.init_gaussian(np.array([2.0, 2.0, 0.0]), np.diag([0.01, 0.01, 0.01]))
    for _ in range(5):
        pf.sensor_update(np.full(len(pf), 10.0))
        pf.resample()
    assert np.all(np.hypot(pf.particles[:, 0] - 2.0, pf.particles[:, 1] - 2.0) < 1.0)
    pf.sensor_update(np.full(len(pf), 0.5))          # the scans stop matching: w_fast falls below w_slow
    pf.resample()
    far = np.hypot(pf.particles[:, 0] - 2.0, pf.particles[:, 1] - 2.0) > 1.0
    assert 0.3 < far.mean() < 1.0
    injected = far.mean()
    pf.sensor_update(np.full(len(pf), 0.5))          # still lost: the averages are kept, it injects again
    pf.resample()
    assert np.mean(np.hypot(pf.particles[:, 0] - 2.0, pf.particles[:, 1] - 2.0) > 1.0) > 0.5 * injected
    for _ in range(30):
        pf.sensor_update(np.full(len(pf), 10.0))     # found again: w_fast climbs back over w_slow
    pf.resample()
    assert pf.w_fast > pf.w_slow


def test_recovery_follows_the_share_of_beams_explained_not_how_many_returned(tb3_world):
    world, grid = tb3_world
    parameters = AmclParameters(laser_model_type='likelihood_field_prob', recovery_alpha_slow=0.001,
                                recovery_alpha_fast=0.1)
    amcl = Amcl(parameters, grid, seed=8)
    s = world.spawn
    robot = Simulation(world, seed=4).add_robot('burger')
    amcl.set_initial_pose((s.x, s.y, s.yaw), np.diag([0.0004, 0.0004, 0.0004]))
    full = amcl.prepare_scan(robot.scan(), LDS_01.angles(), LDS_01.range_min, LDS_01.range_max)
    amcl.update((0.0, 0.0, 0.0), full, LASER)
    for step, kept in enumerate((360, 90, 360, 30, 200)):       # ever fewer or more beams return
        ranges = full.ranges.copy()
        ranges[kept:] = np.inf
        amcl.request_nomotion_update()
        amcl.update((0.0, 0.0, 0.0), full._replace(ranges=ranges), LASER)
        assert amcl.pf.w_fast > 0.9 and amcl.pf.w_slow > 0.9 and amcl.pf.w_fast >= 0.97 * amcl.pf.w_slow
    elsewhere = Simulation(world, seed=4).add_robot('burger', (1.0, 1.6, 2.0))
    lost = amcl.prepare_scan(elsewhere.scan(), LDS_01.angles(), LDS_01.range_min, LDS_01.range_max)
    for _ in range(5):
        amcl.request_nomotion_update()
        amcl.update((0.0, 0.0, 0.0), lost, LASER)
    assert amcl.pf.w_fast < 0.8 * amcl.pf.w_slow
    far = np.hypot(amcl.pf.particles[:, 0] - s.x, amcl.pf.particles[:, 1] - s.y) > 1.0
    assert far.mean() > 0.1 and len(amcl.pf) > parameters.min_particles      # random ones, counted by KLD


def test_a_huge_initial_covariance_spreads_over_free_space_only(tb3_world):
    _, grid = tb3_world
    pf = ParticleFilter(grid, rng=np.random.default_rng(7))
    assert pf.init_gaussian(np.zeros(3), np.diag([200.0, 200.0, 1.0]))
    assert grid.is_free(pf.particles[:, 0], pf.particles[:, 1]).all()
    assert pf.particles[:, 0].std() > 1.0 and pf.particles[:, 1].std() > 1.0    # the whole arena


def test_a_normal_initial_covariance_is_drawn_as_asked_but_not_inside_walls(tb3_world):
    world, grid = tb3_world
    pf = ParticleFilter(grid, rng=np.random.default_rng(8))
    mean = np.array([world.spawn.x, world.spawn.y, 0.3])
    assert pf.init_gaussian(mean, np.diag([0.05, 0.05, 0.02]))
    assert grid.is_free(pf.particles[:, 0], pf.particles[:, 1]).all()
    assert np.allclose(pf.particles.mean(axis=0), mean, atol=0.03)
    assert pf.particles[:, 0].std() == pytest.approx(math.sqrt(0.05), rel=0.15)


def test_a_zero_covariance_puts_every_particle_on_the_pose_even_in_unknown_space(tb3_world):
    _, grid = tb3_world
    pf = ParticleFilter(grid, rng=np.random.default_rng(9))
    assert not pf.init_gaussian(np.array([50.0, 50.0, 1.0]), np.zeros((3, 3)))
    assert np.allclose(pf.particles, [50.0, 50.0, 1.0])


def test_estimate_takes_the_heaviest_cluster_and_the_whole_sets_covariance():
    pf = ParticleFilter(box_map(), rng=np.random.default_rng(10))
    rng = np.random.default_rng(11)
    a = np.column_stack([rng.normal(1.0, 0.05, 300), rng.normal(1.0, 0.05, 300), rng.normal(3.1, 0.02, 300)])
    a[:, 2] = angle_diff(a[:, 2], 0.0)              # straddles +-pi: one cluster all the same
    b = np.column_stack([rng.normal(3.0, 0.05, 100), rng.normal(3.0, 0.05, 100), rng.normal(0.0, 0.02, 100)])
    pf.particles = np.vstack([a, b])
    pf.weights = np.full(400, 1 / 400)
    estimate = pf.estimate()
    assert estimate.clusters == 2 and estimate.weight == pytest.approx(0.75)
    assert np.allclose(estimate.pose[:2], a[:, :2].mean(axis=0))
    assert abs(angle_diff(estimate.pose[2], 3.1)) < 0.01
    assert estimate.covariance[0, 0] == pytest.approx(np.cov(pf.particles[:, 0], bias=True), rel=1e-6)
    assert estimate.covariance[0, 1] == pytest.approx(np.cov(pf.particles[:, 0], pf.particles[:, 1], bias=True)[0, 1])
    assert estimate.covariance[2, 2] > 1.0          # two opposite headings


# -- the whole filter in the simulator ------------------------------------------------------------------------
def run(world, grid, amcl, seconds, command, *, seed=1, start=None):
    """Drive the simulated robot with `command(step, scan) -> (v, w)`, feeding every scan to
    `amcl`; returns the robot and the estimate errors (m, rad) after each published update."""
    sim = Simulation(world, seed=seed)
    robot = sim.add_robot('burger', start, odometry='encoder')
    errors = []
    for step in range(int(seconds / 0.2)):
        robot.command(*command(step, robot.scan(noise=False)))
        sim.step(0.2)
        o = robot.odometry()
        scan = amcl.prepare_scan(robot.scan(), LDS_01.angles(), LDS_01.range_min, LDS_01.range_max)
        if amcl.update((o.x, o.y, o.yaw), scan, LASER).published:
            estimate = compose(amcl.map_to_odom(), np.array([o.x, o.y, o.yaw]))
            p = robot.pose
            errors.append((math.hypot(estimate[0] - p.x, estimate[1] - p.y), abs(angle_diff(estimate[2], p.yaw))))
    return robot, np.array(errors)


def wander(step, scan):
    front = np.concatenate([scan[:35], scan[-35:]])
    blocked = (front < 0).any() or (np.isfinite(front) & (front < 0.45)).any()
    return (0.0, 1.0) if blocked else (0.2, 0.0)


def test_converges_from_half_a_metre_and_30_degrees_off_and_tracks(tb3_world):
    world, grid = tb3_world
    amcl = Amcl(AmclParameters(laser_model_type='likelihood_field_prob'), grid, seed=2)
    s = world.spawn
    amcl.set_initial_pose((s.x + 0.4, s.y - 0.3, s.yaw + math.radians(30)), np.diag([0.25, 0.25, 0.07]))
    robot, errors = run(world, grid, amcl, 20.0, wander)
    assert errors[0][0] > 0.05 or errors[0][1] > 0.05 or len(errors) > 3
    assert errors[-5:, 0].max() < 0.1 and errors[-5:, 1].max() < math.radians(5), errors
    assert amcl.estimate.covariance.max() < 0.07          # what seed 000's node waits for
    assert robot.collisions == 0


def test_no_update_without_motion_unless_asked(tb3_world):
    world, grid = tb3_world
    amcl = Amcl(AmclParameters(), grid, seed=3)
    sim = Simulation(world, seed=1)
    robot = sim.add_robot('burger')
    scan = amcl.prepare_scan(robot.scan(), LDS_01.angles(), LDS_01.range_min, LDS_01.range_max)
    assert amcl.update((0.0, 0.0, 0.0), scan, LASER) == (False, False, False, None)    # no pose yet
    amcl.set_initial_pose((world.spawn.x, world.spawn.y, 0.0), np.diag([0.1, 0.1, 0.05]))
    first = amcl.update((0.0, 0.0, 0.0), scan, LASER)
    assert first.updated and first.published
    assert not amcl.update((0.1, 0.1, 0.1), scan, LASER).updated          # below update_min_d / _a
    assert amcl.update((0.3, 0.1, 0.1), scan, LASER).updated
    amcl.request_nomotion_update()
    assert amcl.update((0.3, 0.1, 0.1), scan, LASER).published


def test_a_scan_with_no_beam_in_range_moves_the_particles_but_publishes_nothing(tb3_world):
    world, grid = tb3_world
    amcl = Amcl(AmclParameters(laser_model_type='likelihood_field_prob'), grid, seed=4)
    robot = Simulation(world, seed=2).add_robot('burger')
    seen = amcl.prepare_scan(robot.scan(), LDS_01.angles(), LDS_01.range_min, LDS_01.range_max)
    blind = amcl.prepare_scan(np.full(len(seen.ranges), np.inf), LDS_01.angles(), LDS_01.range_min, LDS_01.range_max)
    amcl.set_initial_pose((world.spawn.x, world.spawn.y, world.spawn.yaw), np.diag([0.01, 0.01, 0.01]))
    assert amcl.update((0.0, 0.0, 0.0), seen, LASER).published
    map_to_odom, weights = amcl.map_to_odom(), amcl.pf.weights.copy()
    spread = amcl.pf.particles[:, 2].std()
    for step in range(1, 9):                          # 2.4 m with nothing in range
        result = amcl.update((0.3 * step, 0.0, 0.0), blind, LASER)
        assert result.updated and not result.resampled and not result.published
    assert np.array_equal(amcl.map_to_odom(), map_to_odom)      # the pose follows odometry
    assert np.array_equal(amcl.pf.weights, weights) and amcl.pf.particles[:, 2].std() > 2 * spread
    assert amcl.update((2.7, 0.0, 0.0), seen, LASER).published


def test_global_localization_finds_the_robot_in_a_distinctive_world():
    world = load_world('turtlebot3_house')
    start = (world.spawn.x, world.spawn.y)
    grid = world_map(world, start)
    # Seeded: global localization does not always succeed (benchmarks/localization.py measures how often).
    amcl = Amcl(AmclParameters(laser_model_type='likelihood_field_prob', max_particles=10000), grid, seed=2)
    amcl.global_localization()
    assert len(amcl.pf) == 10000 and amcl.pf.particles[:, 0].std() > 1.0
    _, errors = run(world, grid, amcl, 40.0, lambda step, scan: (0.0, 0.6) if step < 50 else wander(step, scan))
    assert errors[-1][0] < 0.1 and errors[-1][1] < math.radians(5), errors[-10:]


def test_map_grid_refuses_bad_input():
    with pytest.raises(ValueError, match='resolution'):
        MapGrid(np.zeros((2, 2)), resolution=0.0)
    with pytest.raises(ValueError, match='rows of 3'):
        MapGrid(np.zeros(7), resolution=0.1, width=3)
    with pytest.raises(ValueError, match='free space'):
        box_map().reachable_from(-5.0, 0.0)
    with pytest.raises(ValueError, match='no free cell'):
        MapGrid(np.full((2, 2), 100), resolution=0.1).sample_free(3, np.random.default_rng())


# -- an honest covariance (issue 34) ------------------------------------------------------------------
def test_the_map_explains_the_scan_at_the_true_pose_and_half_of_it_a_pillar_row_off(tb3_world):
    world, grid = tb3_world
    robot = Simulation(world, seed=3).add_robot('burger', (1.65, 0.55, 0.0))
    amcl = Amcl(AmclParameters(laser_model_type='likelihood_field_prob'), grid, seed=0)
    scan = amcl.prepare_scan(robot.scan(), LDS_01.angles(), LDS_01.range_min, LDS_01.range_max)
    model = amcl.laser_model
    assert model.explained_share(np.array([1.65, 0.55, 0.0]), scan, LASER, within=0.1) > 0.95
    wrong = max(model.explained_share(np.array([1.65, -0.55, yaw]), scan, LASER, within=0.1)
                for yaw in np.linspace(-0.3, 0.3, 13))
    assert wrong < 0.6
    empty = LaserScanData(np.full(5, 3.5), np.linspace(-1, 1, 5), 3.5)      # every beam at range_max
    assert math.isnan(model.explained_share(np.zeros(3), empty, LASER, within=0.1))


def test_covariance_is_widened_only_when_the_scan_does_not_fit():
    from zros.amcl.localizer import FIT_SHARE, LOST_VARIANCE, honest_covariance
    tight = np.diag([0.001, 0.002, 0.01])
    assert np.array_equal(honest_covariance(tight, 0.99), tight)
    assert np.array_equal(honest_covariance(tight, FIT_SHARE), tight)
    assert np.array_equal(honest_covariance(tight, math.nan), tight)
    half = honest_covariance(tight, 0.4)
    floor = LOST_VARIANCE * (FIT_SHARE - 0.4) / FIT_SHARE
    assert np.linalg.eigvalsh(half[:2, :2])[-1] == pytest.approx(floor)
    assert half[2, 2] == tight[2, 2] and half[0, 1] == tight[0, 1] == 0.0
    lost = honest_covariance(tight, 0.0)
    assert np.linalg.eigvalsh(lost[:2, :2])[-1] == pytest.approx(LOST_VARIANCE)
    wide = np.diag([2.0, 0.5, 0.1])
    assert np.array_equal(honest_covariance(wide, 0.0), wide)        # already wider than the floor


def test_a_cloud_settled_on_the_wrong_pose_is_not_reported_confident(tb3_world):
    world, grid = tb3_world
    robot = Simulation(world, seed=5).add_robot('burger', (1.65, 0.55, 0.0))
    amcl = Amcl(AmclParameters(laser_model_type='likelihood_field_prob'), grid, seed=1)
    amcl.set_initial_pose((1.65, -0.55, 0.0), np.diag([0.0004, 0.0004, 0.0001]))      # kidnapped, sure of itself
    scan = amcl.prepare_scan(robot.scan(), LDS_01.angles(), LDS_01.range_min, LDS_01.range_max)
    estimate = amcl.update((0.0, 0.0, 0.0), scan, LASER).estimate
    assert abs(estimate.pose[1] + 0.55) < 0.2 and estimate.explained < 0.6
    assert np.linalg.eigvalsh(estimate.covariance[:2, :2])[-1] > 0.05
    amcl.set_initial_pose((1.65, 0.55, 0.0), np.diag([0.0004, 0.0004, 0.0001]))
    right = amcl.update((0.0, 0.0, 0.0), scan, LASER).estimate
    assert right.explained > 0.95 and right.covariance[:2, :2].max() < 0.01


def test_weighing_gives_each_particles_share_of_explained_beams(tb3_world):
    world, grid = tb3_world
    robot = Simulation(world, seed=3).add_robot('burger', (1.65, 0.55, 0.0))
    amcl = Amcl(AmclParameters(laser_model_type='likelihood_field_prob'), grid, seed=0)
    scan = amcl.prepare_scan(robot.scan(), LDS_01.angles(), LDS_01.range_min, LDS_01.range_max)
    poses = np.array([[1.65, 0.55, 0.0], [1.65, -0.55, 0.0], [0.0, 0.0, 1.0]])
    likelihood, explained = amcl.laser_model.weigh(poses, scan, LASER, within=0.1)
    assert np.array_equal(likelihood, amcl.laser_model.likelihood(poses, scan, LASER))
    assert list(explained) == [amcl.laser_model.explained_share(p, scan, LASER, within=0.1) for p in poses]
    assert explained[0] > 0.95 > explained[1]


def test_recovery_does_not_feed_on_its_own_random_particles_with_the_gentle_model(tb3_world):
    world, grid = tb3_world
    s = world.spawn
    amcl = Amcl(AmclParameters(recovery_alpha_slow=0.001, recovery_alpha_fast=0.1), grid, seed=10)
    robot = Simulation(world, seed=7).add_robot('burger')
    seen = amcl.prepare_scan(robot.scan(), LDS_01.angles(), LDS_01.range_min, LDS_01.range_max)
    amcl.set_initial_pose((s.x, s.y, s.yaw), np.diag([0.01, 0.01, 0.01]))
    amcl.update((0.0, 0.0, 0.0), seen, LASER)
    amcl.request_nomotion_update()
    amcl.update((0.0, 0.0, 0.0), seen, LASER)
    amcl.pf.w_fast *= 0.9                             # one injection: 10 % random particles
    for _ in range(20):
        amcl.request_nomotion_update()
        amcl.update((0.0, 0.0, 0.0), seen, LASER)
    assert amcl.pf.w_fast >= 0.97 * amcl.pf.w_slow     # the reported pose still fits: no more injected
    assert np.linalg.norm(amcl.estimate.pose[:2] - [s.x, s.y]) < 0.1


def test_after_losing_the_robot_only_a_run_of_near_perfect_fits_makes_it_confident_again(tb3_world):
    from zros.amcl.localizer import CONFIRM_ESTIMATES, confirmation
    assert confirmation(None, 0.97) is None and confirmation(None, math.nan) is None
    assert confirmation(None, 0.3) == 0 and confirmation(4, 0.3) == 0
    assert confirmation(4, 0.97) == 0 and confirmation(4, 0.995) == 5 and confirmation(4, math.nan) == 4
    assert confirmation(CONFIRM_ESTIMATES - 1, 1.0) is None
    world, grid = tb3_world
    s = world.spawn
    amcl = Amcl(AmclParameters(laser_model_type='likelihood_field_prob'), grid, seed=9)
    here = Simulation(world, seed=6).add_robot('burger')
    elsewhere = Simulation(world, seed=6).add_robot('burger', (1.0, 1.6, 2.0))
    seen, lost = (amcl.prepare_scan(r.scan(noise=False), LDS_01.angles(), LDS_01.range_min, LDS_01.range_max)
                  for r in (here, elsewhere))
    amcl.set_initial_pose((s.x, s.y, s.yaw), np.diag([0.0004, 0.0004, 0.0004]))

    def variance(scan) -> float:
        amcl.request_nomotion_update()
        return float(np.linalg.eigvalsh(amcl.update((0.0, 0.0, 0.0), scan, LASER).estimate.covariance[:2, :2])[-1])
    assert variance(seen) < 0.05
    assert variance(lost) > 0.5                       # the scan stops fitting: lost
    assert all(variance(seen) > 0.4 for _ in range(CONFIRM_ESTIMATES - 1))    # right again, not yet believed
    assert variance(seen) < 0.05
    amcl.global_localization()
    assert variance(seen) > 0.4                       # a fresh global localization is not believed at once


@pytest.mark.parametrize('model_type', ['likelihood_field', 'likelihood_field_prob'])
def test_scores_looked_up_per_cell_match_the_formula_on_the_end_points(model_type):
    """The scores come from a per-cell table; they must be Nav2's formula on each end point's
    distance, for end points on the map, off it (each side) and through a wall."""
    model = create_laser_model(model_type, thick_wall_map(-1), z_hit=0.5, z_rand=0.5, sigma_hit=0.2, max_dist=2.0,
                               max_beams=8)
    rng = np.random.default_rng(4)
    particles = np.column_stack([rng.uniform(-0.5, 2.5, 50), rng.uniform(-0.5, 2.5, 50), rng.uniform(-4, 4, 50)])
    particles[0] = (0.61, 1.0, 0.0)                                  # its first beam comes out through the wall
    ranges, bearings = np.array([0.52, 0.3, 1.0, 3.0]), np.array([0.0, 1.0, -2.5, 3.0])
    scan = LaserScanData(ranges, bearings, 3.5)
    distance = model.end_distances(particles, ranges, bearings, (0.05, 0.02, 0.1))
    assert distance[0, 0] == 2.0 and (distance == 2.0).any(axis=1).sum() > 5 and (distance < 0.1).any()
    pz = 0.5 * np.exp(-distance ** 2 / (2 * 0.2 ** 2)) + 0.5 / 3.5
    expected = np.prod(pz, axis=1) if model_type == 'likelihood_field_prob' else 1.0 + np.sum(pz ** 3, axis=1)
    likelihood, explained = model.weigh(particles, scan, (0.05, 0.02, 0.1), within=None)
    assert likelihood == pytest.approx(expected, rel=1e-12) and explained is None


def test_without_recovery_the_fit_is_not_computed_and_the_filter_runs_the_same(tb3_world):
    """Recovery off (the shipped files): the share of explained beams per particle only fed
    recovery's averages, so it is skipped; the particles come out as they did with it."""
    world, grid = tb3_world
    sim = Simulation(world, seed=2)
    robot = sim.add_robot('burger')
    scans = []
    for _ in range(12):
        robot.command(0.2, 0.3)
        sim.step(0.2)
        scans.append(robot.scan())
    runs = []
    for recovery in (0.0, 1e-9):
        amcl = Amcl(AmclParameters(laser_model_type='likelihood_field_prob', recovery_alpha_slow=recovery), grid, seed=3)
        amcl.set_initial_pose((world.spawn.x, world.spawn.y, world.spawn.yaw), np.diag([0.05, 0.05, 0.02]))
        for i, ranges in enumerate(scans):
            scan = amcl.prepare_scan(ranges, LDS_01.angles(), LDS_01.range_min, LDS_01.range_max)
            amcl.request_nomotion_update()
            amcl.update((0.3 * i, 0.0, 0.0), scan, LASER)
        runs.append(amcl)
    assert runs[0].pf.w_slow == 0.0 < runs[1].pf.w_slow          # the fit was taken only with recovery on
    assert np.array_equal(runs[0].pf.particles, runs[1].pf.particles)
