"""turtlebot3_gazebo's .world files: written by zros from its YAML worlds, they read back
(through zros.sim.sdf, as any Gazebo world file) to the same 2D world."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from zros.sim import LDS_01, load_world, parse_world, rasterize
from zros.sim.raycast import cast_fan
from zros.sim.sdf import parse_sdf_world
from zros.sim.sdf_writer import world_to_sdf

WORLDS_DIR = Path(__file__).resolve().parents[2] / 'nodes' / 'turtlebot3_gazebo' / 'worlds'
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
    # The shipped file is what the tool writes today (rerun tools/write_world_files.py if not).
    assert path.read_text(encoding='utf-8') == world_to_sdf(yaml_world, note=(
        f'written by zros (tools/write_world_files.py) from zros/sim/worlds/{name}.yaml; edit that file and rerun'))


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
