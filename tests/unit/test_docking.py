"""opennav_docking's geometry as plain code: dock databases, the staging pose, and the smooth
control law driving a simulated unicycle onto a dock (forwards) and back off it (backwards)."""
from __future__ import annotations

import math

import pytest

from zros.navigation.docking import (ControlLaw, Dock, DockDatabaseError, approach_target, is_within,
                                     load_dock_database, parse_docks, staging_pose, to_robot_frame)


def _drive(law: ControlLaw, robot: tuple, target: tuple, done, *, backward: bool = False,
           dt: float = 0.02, limit_s: float = 60.0) -> tuple[tuple, float]:
    """Integrate a unicycle under the law aimed at `target` until `done(robot)`; (robot, time)."""
    x, y, yaw = robot
    t = 0.0
    while not done((x, y, yaw)) and t < limit_s:
        v, w = law.velocity(to_robot_frame((x, y, yaw), target), backward=backward)
        assert abs(v) <= law.v_linear_max + 1e-9 and abs(w) <= law.v_angular_max + 1e-9
        x, y, yaw = x + v * dt * math.cos(yaw), y + v * dt * math.sin(yaw), yaw + w * dt
        t += dt
    return (x, y, yaw), t


def test_staging_pose_is_behind_the_dock_along_its_heading():
    assert staging_pose((1.0, 2.0, 0.0)) == pytest.approx((0.3, 2.0, 0.0))
    x, y, yaw = staging_pose((0.0, 0.0, math.pi / 2), x_offset=-0.5, yaw_offset=math.pi)
    assert (x, y) == pytest.approx((0.0, -0.5)) and abs(yaw) == pytest.approx(math.pi / 2)
    assert approach_target((0.0, 0.0, math.pi / 2))[:2] == pytest.approx((0.0, 0.25))
    assert to_robot_frame((1.0, 1.0, math.pi / 2), (1.0, 2.0, math.pi / 2)) == pytest.approx((1.0, 0.0, 0.0))
    assert is_within((0.0, 0.01, 0.0), (0.0, 0.0, 0.05), 0.05, 0.1)
    assert not is_within((0.0, 0.01, 0.0), (0.0, 0.0, 0.5), 0.05, 0.1)


@pytest.mark.parametrize('offset', [(0.0, 0.0, 0.0), (0.05, 0.15, 0.3), (-0.1, -0.2, -0.4)])
def test_the_law_drives_from_near_staging_onto_the_dock(offset):
    """Nav2 Jazzy's bringup numbers: 0.15 m/s, docking_threshold 0.05 m, staging 0.7 m out."""
    law = ControlLaw(v_linear_min=0.15, v_linear_max=0.15)
    dock = (2.0, 1.0, math.pi / 4)
    sx, sy, syaw = staging_pose(dock)
    start = (sx + offset[0], sy + offset[1], syaw + offset[2])
    robot, t = _drive(law, start, approach_target(dock), lambda r: is_within(r, dock, 0.05))
    assert is_within(robot, dock, 0.05), robot
    assert abs(math.atan2(math.sin(robot[2] - dock[2]), math.cos(robot[2] - dock[2]))) < 0.25
    assert t < 10.0


def test_undocking_backs_off_to_the_staging_pose():
    law = ControlLaw(v_linear_min=0.15, v_linear_max=0.15)
    docked = (2.0, 1.0, math.pi / 4)
    staging = staging_pose(docked)
    robot, _ = _drive(law, docked, staging, lambda r: is_within(r, staging, 0.05, 0.1), backward=True)
    assert is_within(robot, staging, 0.05, 0.1)
    v, _ = law.velocity(to_robot_frame(docked, staging), backward=True)
    assert v < 0.0


def test_control_law_limits_and_parameter_names():
    law = ControlLaw()
    assert law.velocity((0.0, 0.0, 0.0)) == (0.0, 0.0)
    v, w = law.velocity((3.0, 0.0, 0.0))
    assert v == pytest.approx(law.v_linear_max) and w == pytest.approx(0.0)
    v, w = law.velocity((0.05, 0.5, 0.0))              # nearly beside the robot: a sharp turn
    assert w == pytest.approx(law.v_angular_max)       # the turn rate is capped, and the speed
    assert 0.0 < v < law.v_linear_min                  # drops below the minimum to keep the curve
    seen = {}
    built = ControlLaw.from_params(lambda name, default: seen.setdefault(name, default * 2))
    assert 'controller.lambda' in seen and 'controller.k_phi' in seen
    assert built.k_phi == 6.0 and built.lambda_ == 4.0


def test_dock_databases(tmp_path):
    path = tmp_path / 'docks.yaml'
    path.write_text('docks:\n  home:\n    type: simple_charging_dock\n    frame: odom\n    pose: [1.0, 2.0, 0.5]\n'
                    '  spare:\n    type: simple_charging_dock\n    pose: [0, 0, 0]\n    id: "7"\n')
    docks = load_dock_database(path)
    assert docks['home'] == Dock('home', 'simple_charging_dock', 'odom', (1.0, 2.0, 0.5))
    assert docks['spare'].frame == 'map' and docks['spare'].id == '7'
    for text, fragment in [('docks: {a: {pose: [0, 0, 0]}}', 'no dock "type"'),
                           ('docks: {a: {type: t, pose: [0, 0]}}', 'no valid "pose"'),
                           ('other: 1', "does not contain 'docks'"),
                           ('docks: [', 'is not YAML')]:
        path.write_text(text)
        with pytest.raises(DockDatabaseError, match=fragment) as err:
            load_dock_database(path)
        assert '\n' not in str(err.value)
    with pytest.raises(DockDatabaseError, match='Cannot read'):
        load_dock_database(tmp_path / 'missing.yaml')
    with pytest.raises(DockDatabaseError, match='not three numbers'):
        parse_docks({'a': {'type': 't', 'pose': ['x', 0, 0]}}, 'parameters')
