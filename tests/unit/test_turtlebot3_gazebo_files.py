"""turtlebot3_gazebo's files at upstream's paths, written by tools/write_turtlebot3_gazebo.py: the
.world files read back (through zros.sim.sdf, as any Gazebo world file) to the same 2D worlds,
the model.sdf files (through zros.sim.model_file) to the robots zros simulates, and the URDFs
give robot_state_publisher the frames the simulator uses."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from conftest import load_tool
from zros.sim import LDS_01, load_world, parse_world, rasterize
from zros.sim.raycast import cast_fan
from zros.sim.sdf import parse_sdf_world
from zros.sim.sdf_writer import world_to_sdf

ROOT = Path(__file__).resolve().parents[2]
PACKAGE = ROOT / 'nodes' / 'turtlebot3_gazebo'
WORLDS_DIR = PACKAGE / 'worlds'
NAMES = ('empty_world', 'turtlebot3_world', 'turtlebot3_house', 'turtlebot3_bighouse')


def _same_world(a, b, *, tolerance: float = 1e-9) -> None:
    """Same circles, same exact raster, and the same lidar ranges from free points all over it."""
    assert np.allclose(np.sort(a.circles, axis=0), np.sort(b.circles, axis=0), atol=tolerance)
    if a.is_empty:
        assert b.is_empty
        return
    ra, rb = rasterize(a, 0.05), rasterize(b, 0.05)
    assert ra.origin == pytest.approx(rb.origin) and np.array_equal(ra.cells, rb.cells)
    x0, y0, x1, y1 = a.bounds()
    grid = np.stack(np.meshgrid(np.linspace(x0, x1, 9), np.linspace(y0, y1, 9)), axis=-1).reshape(-1, 2)
    free = grid[~a.contains(grid) & (a.distance(grid) > 0.05)]
    assert len(free) > 5
    for x, y in free:
        fan = [cast_fan((x, y), 0.0, LDS_01.angle_increment, 360, w.edges, w.circles, LDS_01.range_max)
               for w in (a, b)]
        assert np.allclose(fan[0], fan[1], atol=max(tolerance, 1e-9), equal_nan=True)


@pytest.mark.parametrize('name', NAMES)
def test_each_shipped_world_file_reads_back_to_its_yaml_world(name: str) -> None:
    yaml_world = load_world(name)
    path = WORLDS_DIR / f'{name}.world'
    sdf_world = load_world(path)
    assert sdf_world.name == name
    _same_world(yaml_world, sdf_world)


def test_segments_become_millimetre_boxes_and_odd_polygons_are_refused() -> None:
    world = parse_world('name: w\nobstacles:\n- segment: {from: [-1, -1], to: [1, 0.5]}\n'
                        '- polygon: {points: [[2, 0], [3, 0], [2.5, 1]]}\n')
    back = parse_sdf_world(world_to_sdf(world))
    ranges = [cast_fan((0.0, 1.0), 0.0, 0.01, 629, w.edges, w.circles, 5.0) for w in (world, back)]
    same = np.isclose(ranges[0], ranges[1], atol=0.001)
    assert same.mean() > 0.99           # all but a beam grazing a wall's end, where the box is 0.5 mm longer
    from zros.sim.world import World
    odd = World('odd', polygons=((np.zeros((3, 2)), np.ones((4, 2))),))
    with pytest.raises(ValueError, match='polygon 0 has 2 loops'):
        world_to_sdf(odd)


def test_the_shipped_files_are_what_the_tool_writes_today() -> None:
    """Rerun tools/write_turtlebot3_gazebo.py after changing a YAML world or a TurtleBot3 number."""
    written = load_tool('write_turtlebot3_gazebo').files()
    assert len(written) == 4 + 3 * 3
    for relative, text in written.items():
        assert (PACKAGE / relative).read_text(encoding='utf-8') == text, relative


@pytest.mark.parametrize('model', ['burger', 'waffle', 'waffle_pi'])
def test_each_model_sdf_reads_back_to_the_robot_zros_simulates(model: str) -> None:
    from zros.sim.model_file import robot_from_xml, turtlebot3_model
    text = (PACKAGE / 'models' / f'turtlebot3_{model}' / 'model.sdf').read_text(encoding='utf-8')
    robot = robot_from_xml(text, fallback='burger')
    assert robot == turtlebot3_model(model)
    assert robot.drive.odometry_source == 'world' and robot.drive.publish_odom and robot.drive.publish_odom_tf
    assert (robot.scan.topic, robot.scan.frame, robot.scan.rate) == ('scan', 'base_scan', 5.0)


@pytest.mark.parametrize('model', ['burger', 'waffle', 'waffle_pi'])
def test_each_urdf_has_the_simulators_fixed_frames_and_wheel_joints(model: str) -> None:
    from zros.sim import robot_spec
    from zros.urdf.model import parse_urdf
    from nodes.turtlebot3_gazebo._frames import WHEEL_JOINTS, static_frames
    robot = parse_urdf((PACKAGE / 'urdf' / f'turtlebot3_{model}.urdf').read_text(encoding='utf-8'))
    fixed = {(j.parent, j.child): tuple(j.origin.xyz) for j in robot.joints.values() if j.type == 'fixed'}
    simulated = {(parent, child): pytest.approx(xyz) for parent, child, xyz in static_frames(robot_spec(model))}
    assert {key: fixed[key] for key in simulated} == simulated
    cameras = {child for parent, child in fixed.keys() - simulated.keys()}
    assert cameras == {'burger': set(),
                       'waffle': {'camera_link', 'camera_rgb_frame', 'camera_rgb_optical_frame',
                                  'camera_depth_frame', 'camera_depth_optical_frame'},
                       'waffle_pi': {'camera_link', 'camera_rgb_frame', 'camera_rgb_optical_frame'}}[model]
    optical = next(j for j in robot.joints.values() if j.child == 'camera_rgb_optical_frame') if cameras else None
    assert optical is None or tuple(optical.origin.rpy) == pytest.approx((-1.57, 0.0, -1.57))
    assert all(tuple(j.origin.rpy) == pytest.approx((-1.57, 0.0, 0.0))
               for j in robot.joints.values() if j.child.startswith('caster_'))
    assert {j.name for j in robot.joints.values() if j.type == 'continuous'} == set(WHEEL_JOINTS)
