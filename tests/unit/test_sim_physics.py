"""zros.sim's robot: drive, limits, walls, collisions, odometry noise, lidar, determinism."""
from __future__ import annotations

import math

import numpy as np
import pytest

from zros.sim import BURGER, LDS_01, SimError, Simulation, load_world, parse_world

WALL_AT_1M = parse_world('obstacles:\n- segment: {from: [1.0, -5.0], to: [1.0, 5.0]}\n')


def test_driving_0_2_m_s_for_5_s_moves_1_m() -> None:
    sim = Simulation(load_world('empty_world'))
    robot = sim.add_robot('burger', (0.0, 0.0, 0.0))
    robot.command(0.2, 0.0)
    sim.step(5.0)
    robot.command(0.0, 0.0)
    sim.step(1.0)
    assert robot.pose.x == pytest.approx(1.0, rel=0.02)
    assert abs(robot.pose.y) < 1e-9 and robot.velocity == (0.0, 0.0)


def test_speed_and_acceleration_limits_are_the_burgers() -> None:
    sim = Simulation(load_world('empty_world'))
    robot = sim.add_robot('burger', (0.0, 0.0, 0.0))
    robot.command(5.0, 0.0)
    sim.step(0.1)
    assert robot.velocity[0] == pytest.approx(0.1, abs=0.006)      # 1 m/s^2 at the wheels
    sim.step(1.0)
    assert robot.velocity[0] == pytest.approx(BURGER.max_linear)
    robot.command(0.0, -10.0)
    sim.step(1.0)
    assert robot.velocity == pytest.approx((0.0, -BURGER.max_angular))
    with pytest.raises(ValueError, match='finite'):
        robot.command(float('nan'), 0.0)


def test_encoder_odometry_without_slip_is_the_truth_seen_from_the_spawn_pose() -> None:
    sim = Simulation(load_world('empty_world'))
    robot = sim.add_robot('burger', (1.0, 2.0, 0.5), slip_stddev=0.0, odometry='encoder')
    for linear, angular, seconds in [(0.2, 0.0, 3), (0.15, 0.8, 7.3), (-0.1, -2.84, 3), (0.0, 0.0, 1)]:
        robot.command(linear, angular)
        sim.step(seconds)
    truth, odom = robot.pose, robot.odometry()
    c, s = math.cos(0.5), math.sin(0.5)      # odom starts at the spawn pose
    assert truth.x == pytest.approx(1.0 + c * odom.x - s * odom.y, abs=1e-9)
    assert truth.y == pytest.approx(2.0 + s * odom.x + c * odom.y, abs=1e-9)
    assert math.remainder(truth.yaw - odom.yaw - 0.5, 2 * math.pi) == pytest.approx(0.0, abs=1e-9)


def test_world_odometry_is_the_true_pose_in_the_world_frame_even_after_a_teleport() -> None:
    """Gazebo's diff drive, by default: odom is the world frame, so a robot spawned at
    (-2.0, -0.5) starts with odometry (-2.0, -0.5), and slip does not touch it."""
    sim = Simulation(load_world('turtlebot3_world'), seed=3)
    robot = sim.add_robot('burger', (-2.0, -0.5, 0.3), slip_stddev=0.05)
    assert robot.odometry_source == 'world'
    start = robot.odometry()
    assert (start.x, start.y, start.yaw) == (-2.0, -0.5, pytest.approx(0.3))
    robot.command(0.2, 0.4)
    sim.step(2.0)
    odom, truth = robot.odometry(), robot.pose
    assert (odom.x, odom.y, odom.yaw) == (truth.x, truth.y, truth.yaw)
    assert (odom.linear, odom.angular) == pytest.approx(robot.velocity)
    sim.teleport('burger', (-2.0, 1.0, 0.0))
    moved = robot.odometry()
    assert (moved.x, moved.y, moved.yaw) == (-2.0, 1.0, 0.0)


def test_odometry_source_takes_gazebos_names_and_numbers_and_refuses_others() -> None:
    sim = Simulation(load_world('empty_world'))
    assert [sim.add_robot(f'r{i}', (2.0 * i, 0.0, 0.0), odometry=value).odometry_source
            for i, value in enumerate(['world', 'encoder', 1, 0, '0'])] == ['world', 'encoder', 'world', 'encoder', 'encoder']
    with pytest.raises(ValueError, match="'world' \\(1\\) or 'encoder' \\(0\\), got 'gps'"):
        sim.add_robot('bad', (20.0, 0.0, 0.0), odometry='gps')
    assert 'bad' not in sim.robots


def test_odometry_drifts_by_the_configured_slip_only() -> None:
    slip, distance = 0.01, 2.0
    wheel_errors, yaw_errors = [], []
    for seed in range(24):
        sim = Simulation(load_world('empty_world'), seed=seed)
        robot = sim.add_robot('burger', (0.0, 0.0, 0.0), slip_stddev=slip, odometry=0)   # Gazebo's ENCODER
        robot.command(0.2, 0.0)
        sim.step(distance / 0.2)
        robot.command(0.0, 0.0)
        sim.step(0.5)
        assert robot.pose.x == pytest.approx(distance, abs=1e-9)      # the truth drives straight
        wheel_errors += [p * BURGER.wheel_radius - distance for p in robot.wheel_positions]
        yaw_errors.append(robot.odometry().yaw)
    # Each wheel's travel error has variance slip^2 * distance; heading error is their difference
    # over the wheel separation.
    sigma_wheel = slip * math.sqrt(distance)
    sigma_yaw = math.sqrt(2.0) * sigma_wheel / BURGER.wheel_separation
    for errors, sigma in ((np.array(wheel_errors), sigma_wheel), (np.array(yaw_errors), sigma_yaw)):
        assert np.abs(errors).max() < 4 * sigma
        assert 0.6 * sigma < errors.std() < 1.5 * sigma


def test_the_robot_never_passes_a_wall_at_full_speed_and_each_bump_counts() -> None:
    world = load_world('turtlebot3_world')
    sim = Simulation(world)
    robot = sim.add_robot('burger', (0.55, 0.55, 0.0))
    bumps = []
    sim.on_collision = lambda r: bumps.append(r.name)
    closest = np.inf
    for heading in np.linspace(-math.pi, math.pi, 12, endpoint=False):
        sim.teleport('burger', (0.55, 0.55, heading))
        before = robot.collisions
        robot.command(BURGER.max_linear, 0.0)
        for _ in range(80):        # 16 s: far enough to reach a pillar or the wall, then push on it
            sim.step(0.2)
            p = robot.pose
            assert not world.contains([[p.x, p.y]])[0]
            closest = min(closest, world.distance([[p.x, p.y]])[0])
        assert robot.in_contact and robot.collisions > before   # a pillar grazed, then a wall: 2
    assert closest > BURGER.body_radius - 0.0015           # at most 1.5 mm into a surface
    assert robot.collisions == len(bumps)


def test_pushing_and_sliding_along_a_wall_is_one_collision() -> None:
    sim = Simulation(WALL_AT_1M)
    robot = sim.add_robot('burger', (0.0, 0.0, 0.5))
    robot.command(BURGER.max_linear, 0.0)
    sim.step(20.0)
    assert robot.in_contact and robot.collisions == 1
    assert robot.pose.x == pytest.approx(1.0 - BURGER.body_radius, abs=0.001)
    y = robot.pose.y
    sim.step(1.0)                                          # slides at the tangential speed
    assert robot.pose.y - y == pytest.approx(BURGER.max_linear * math.sin(0.5), abs=0.002)


def test_lidar_reads_the_distance_to_a_known_wall() -> None:
    sim = Simulation(WALL_AT_1M, seed=3)
    robot = sim.add_robot('burger', (0.0, 0.0, 0.0))
    sensor_x = BURGER.lidar_mount[0]
    ranges = np.stack([robot.scan() for _ in range(50)])
    assert ranges.shape == (50, 360) and ranges.dtype == np.float32
    ahead = ranges[:, 0]
    assert abs(ahead.mean() - (1.0 - sensor_x)) < 0.01
    assert 0.005 < ahead.std() < 0.015                    # sigma = 0.01 m
    exact = robot.scan(noise=False)
    angles = LDS_01.angles()
    facing = np.cos(angles) > (1.0 - sensor_x) / LDS_01.range_max + 1e-6   # beams that can reach it
    assert np.allclose(exact[facing], (1.0 - sensor_x) / np.cos(angles[facing]), atol=1e-5)
    assert np.isinf(exact[~facing]).all() and (exact[~facing] > 0).all()


def test_lidar_reports_too_close_as_minus_inf_and_sees_other_robots() -> None:
    sim = Simulation(WALL_AT_1M)
    robot = sim.add_robot('burger', (0.5, 0.0, math.pi))   # backs onto the wall: 0.07 m behind the lidar
    robot.command(-0.1, 0.0)
    sim.step(5.0)
    assert robot.in_contact
    behind = robot.scan(noise=False)[180]
    assert behind == -np.inf
    other = sim.add_robot('other', (-1.0, 0.0, 0.0))
    ahead = robot.scan(noise=False)[0]
    gap = robot.sensor_pose(BURGER.lidar_mount)[0] - other.sensor_pose(BURGER.lidar_mount)[0]
    assert ahead == pytest.approx(gap - BURGER.lidar_housing_radius, abs=1e-4)


def test_same_seed_and_commands_give_the_same_trajectory() -> None:
    def run(seed: int) -> tuple:
        sim = Simulation(load_world('turtlebot3_world'), seed=seed)
        robot = sim.add_robot('burger')
        trace = []
        for k in range(30):
            robot.command(0.22 * math.sin(k), 2.0 * math.cos(0.7 * k))
            sim.step(0.5)
            trace.append((robot.pose, robot.odometry(), robot.scan().tobytes(), robot.imu()))
        return tuple(trace)
    assert run(1) == run(1)
    assert run(1) != run(2)


def test_reset_restarts_time_poses_odometry_and_noise() -> None:
    sim = Simulation(load_world('turtlebot3_world'), seed=5)
    robot = sim.add_robot('burger')
    first_scan = robot.scan()
    robot.command(0.2, 0.5)
    sim.step(3.0)
    sim.reset()
    assert sim.time_ns == 0 and robot.pose == sim.world.spawn and robot.odometry().x == sim.world.spawn.x
    assert np.array_equal(robot.scan(), first_scan)
    assert robot.velocity == (0.0, 0.0)


def test_command_timeout_stops_a_robot_that_hears_nothing() -> None:
    stops: list[float] = []
    sim = Simulation(load_world('empty_world'), on_command_timeout=lambda r: stops.append(sim.time))
    robot = sim.add_robot('burger', (0.0, 0.0, 0.0))
    robot.command_timeout = 0.5
    robot.command(0.2, 0.0)
    sim.step(3.0)
    assert robot.velocity == (0.0, 0.0)
    assert robot.pose.x == pytest.approx(0.2 * 0.5 - 0.2 ** 2 / 2 / 1.0, abs=0.003)   # less the run-up, no run-down
    assert len(stops) == 1 and 0.5 < stops[0] <= 0.5 + sim.dt + 1e-9      # reported once, to the step
    robot.command_timeout = None          # the default: the last command holds
    robot.command(0.2, 0.0)
    sim.step(3.0)
    assert robot.velocity[0] == pytest.approx(0.2) and len(stops) == 1
    robot.command(0.0, 0.0)               # at rest when the timeout passes: nothing to report
    robot.command_timeout = 0.5
    sim.step(3.0)
    assert len(stops) == 1


def test_the_watchdog_stops_at_once_where_a_zero_command_decelerates() -> None:
    """A zero command is paced by the wheels' acceleration limit (Gazebo's plugin); the timeout
    is the base's watchdog, which zeroes the motors: no movement after the step it fires in."""
    sim = Simulation(load_world('empty_world'))
    braked, cut = sim.add_robot('braked', (0.0, 0.0, 0.0)), sim.add_robot('cut', (0.0, 2.0, 0.0))
    cut.command_timeout = 0.5
    for robot in (braked, cut):
        robot.command(0.2, 0.0)
    sim.step(0.5)
    braked.command(0.0, 0.0)
    sim.step(steps=2)
    x_braked, x_cut = braked.pose.x, cut.pose.x
    sim.step(1.0)
    assert braked.pose.x - x_braked == pytest.approx(0.2 ** 2 / 2 / 1.0, abs=0.002)   # v^2/2a at 1 m/s^2
    assert cut.pose.x == x_cut and cut.velocity == (0.0, 0.0)
    cut.command(0.0, 0.5)                 # a new command re-arms it: one report per silence
    sim.step(1.0)
    assert cut.velocity == (0.0, 0.0)


def test_bad_spawns_and_teleports_are_refused() -> None:
    sim = Simulation(load_world('turtlebot3_world'))
    sim.add_robot('burger', odometry='encoder')
    with pytest.raises(SimError, match='already exists'):
        sim.add_robot('burger', (0.5, 0.5, 0.0))
    with pytest.raises(SimError, match='obstacle'):
        sim.add_robot('second', (0.0, 0.0, 0.0))           # on a pillar
    with pytest.raises(SimError, match="overlaps robot 'burger'"):
        sim.add_robot('second', (-2.1, -0.5, 0.0))
    with pytest.raises(SimError, match='obstacle'):
        sim.teleport('burger', (1.1, 1.1, 0.0))
    with pytest.raises(SimError, match="no robot named 'ghost'"):
        sim.teleport('ghost', (0.5, 0.5, 0.0))
    sim.teleport('burger', (0.55, 0.55, 1.0))
    assert sim.robot('burger').pose.x == 0.55 and sim.robot('burger').odometry().x == 0.0   # encoders feel nothing


def test_the_robot_pushes_a_loose_box_and_its_lidar_sees_it_move() -> None:
    from zros.sim import Pose2D
    from zros.sim.sdf import parse_sdf_world
    world = parse_sdf_world(
        '<sdf version="1.6"><world name="w"><model name="box"><pose>0.6 0 0.1 0 0 0</pose><link name="l">'
        '<inertial><mass>0.5</mass></inertial><collision name="c"><geometry><box><size>0.2 0.2 0.2</size></box>'
        '</geometry></collision></link></model></world></sdf>')
    sim = Simulation(world)
    robot = sim.add_robot('burger', (0.0, 0.0, 0.0))
    lidar_x = robot.sensor_pose(BURGER.lidar_mount)[0]
    assert robot.scan(noise=False)[0] == pytest.approx(0.5 - lidar_x, abs=1e-3)      # the box's near face
    robot.command(0.2, 0.0)
    sim.step(5.0)
    box = sim.body_pose('box')
    assert box.x > 1.0 and abs(box.y) < 1e-6                       # pushed straight ahead
    assert robot.pose.x == pytest.approx(0.97, abs=0.02)           # the robot hardly slowed
    assert robot.scan(noise=False)[0] == pytest.approx(box.x - 0.1 - robot.sensor_pose(BURGER.lidar_mount)[0],
                                                       abs=2e-3)
    robot.command(0.0, 0.0)
    sim.step(2.0)
    assert sim.body_pose('box').x - box.x < 0.1                     # the floor stops it
    sim.reset()
    assert sim.body_pose('box') == Pose2D(0.6, 0.0, 0.0)                # back where the file puts it
    with pytest.raises(SimError, match="no pushable body named 'crate'"):
        sim.body_pose('crate')
