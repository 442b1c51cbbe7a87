"""zros.sim's worlds: the shipped files, the loader's errors, the exact raster, the ray caster."""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from zros.sim import LDS_01, WorldFileError, load_world, parse_world, rasterize, world_names
from zros.sim.raycast import cast_fan


def test_shipped_worlds_load_with_their_spawn_poses() -> None:
    assert world_names() == ['corridor', 'empty_world', 'turtlebot3_bighouse', 'turtlebot3_house', 'turtlebot3_world']
    world = load_world('turtlebot3_world')
    assert (world.spawn.x, world.spawn.y) == (-2.0, -0.5)
    assert len(world.circles) == 9 and len(world.edges) == 12 + 5 * 6
    house = load_world('turtlebot3_house')
    assert house.bounds()[0] < -7.5 and house.bounds()[2] > 7.5
    assert load_world('empty_world').is_empty
    for name in world_names():   # nobody starts inside a wall
        w = load_world(name)
        assert not w.collides(w.spawn.x, w.spawn.y, 0.105)


def test_the_bighouse_is_big_closed_and_every_room_is_reachable() -> None:
    """seed 000's bighouse (zros's own, docs/robot.md): 2-3 times turtlebot3_house, rooms deeper
    than the lidar's range, and a burger can drive from the spawn into every room."""
    from scipy import ndimage
    big, house = load_world('turtlebot3_bighouse'), load_world('turtlebot3_house')
    area = lambda w: (w.bounds()[2] - w.bounds()[0]) * (w.bounds()[3] - w.bounds()[1])   # noqa: E731
    assert 2.0 <= area(big) / area(house) <= 3.0
    raster = rasterize(big, 0.05)
    free = ~ndimage.binary_dilation(raster.cells, iterations=3)        # 0.15 m: a burger's radius and a margin
    regions, _ = ndimage.label(free)

    def region(x: float, y: float) -> int:
        col, row = ((np.array([x, y]) - raster.origin) / 0.05).astype(int)
        return regions[row, col]
    start = region(big.spawn.x, big.spawn.y)
    assert start != 0 and region(2.7, -1.1) == start                    # the course's other start
    rooms = [(-9, 2), (-10.5, 6.5), (-3, 5.5), (3, 6), (9, 4.5), (-10, -5), (-5, -3), (1, -5), (8, -3.5)]
    assert [region(x, y) for x, y in rooms] == [start] * len(rooms)
    assert region(-13.0, 0.0) != start                                  # closed: outside is apart


def test_turtlebot3_world_geometry_matches_the_reference() -> None:
    world = load_world('turtlebot3_world')
    # Inside the hexagonal wall's flat sides (apothem 2.54) and outside its outer face (2.8575).
    assert not world.contains([[0.0, 2.5]])[0] and world.contains([[0.0, 2.6]])[0]
    assert world.contains([[0.0, 2.85]])[0] and not world.contains([[0.0, 2.87]])[0]
    assert world.contains([[-1.1, 1.1]])[0] and not world.contains([[-1.1, 1.26]])[0]   # a pillar
    assert world.contains([[3.5, 0.0]])[0]                                             # the head
    assert world.distance([[0.0, 0.0]])[0] == pytest.approx(0.15)


def _write(tmp_path: Path, text: str, name: str = 'bad.yaml') -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


@pytest.mark.parametrize('text, line, fragment', [
    ('obstacles:\n- circle: {center: [0, 0], radius: -1}\n', 2, 'obstacles[0].circle.radius: must be > 0'),
    ('obstacles:\n- circle: {center: [0, 0]}\n', 2, "obstacles[0].circle: missing 'radius'"),
    ('obstacles:\n- box: {center: [0, 0], size: [1, 1]}\n- blob: {}\n', 3, 'obstacles[1].blob: unknown key'),
    ('obstacles:\n  - polygon:\n      points: [[0, 0], [1, 0]]\n', 3, 'at least 3 points'),
    ('name: w\nspawn: {x: 1, y: oops}\nobstacles: []\n', 2, "spawn.y: expected a number, got 'oops'"),
    ('obstacles:\n- segment: {from: [0, 0], to: [1]}\n', 2, 'obstacles[0].segment.to: expected [x, y]'),
    ('obstacles:\n- ring: {center: [0, 0], sides: 6, inner_circumradius: 2, outer_circumradius: 1}\n', 2,
     'outer_circumradius: must be > inner_circumradius'),
    ('obstacles: [\n', 2, 'invalid YAML'),
    ('spawn: {x: 0, y: 0}\n', 1, "missing 'obstacles'"),
])
def test_bad_world_files_name_file_line_and_key(tmp_path: Path, text: str, line: int, fragment: str) -> None:
    path = _write(tmp_path, text)
    with pytest.raises(WorldFileError) as info:
        load_world(path)
    message = str(info.value)
    assert message.startswith(f'{path}:{line}:'), message
    assert fragment in message and '\n' not in message


def test_unknown_world_names_and_paths_are_one_line_errors(tmp_path: Path) -> None:
    with pytest.raises(WorldFileError, match="unknown world 'moon'.*turtlebot3_world"):
        load_world('moon')
    with pytest.raises(WorldFileError, match='no such world file'):
        load_world(tmp_path / 'missing.yaml')


def test_json_world_files_work_too(tmp_path: Path) -> None:
    path = _write(tmp_path, '{"name": "j", "obstacles": [{"circle": {"center": [1, 2], "radius": 0.5}}]}',
                  'w.json')
    world = load_world(path)
    assert world.name == 'j' and world.circles.tolist() == [[1.0, 2.0, 0.5]]


def _supersampled(world, raster, samples: int) -> np.ndarray:
    """Which cells contain at least one of samples x samples interior points inside an obstacle."""
    res, (ox, oy) = raster.resolution, raster.origin
    h, w = raster.cells.shape
    offsets = (np.arange(samples) + 0.5) / samples
    xs = ox + (np.arange(w)[:, None] + offsets[None, :]).ravel() * res
    ys = oy + (np.arange(h)[:, None] + offsets[None, :]).ravel() * res
    gx, gy = np.meshgrid(xs, ys)
    inside = world.contains(np.column_stack([gx.ravel(), gy.ravel()])).reshape(h * samples, w * samples)
    return inside.reshape(h, samples, w, samples).any(axis=(1, 3))


@pytest.mark.parametrize('resolution', [0.05, 0.137])
def test_raster_is_exact_against_dense_sampling(resolution: float) -> None:
    world = parse_world('obstacles:\n'
                        '- circle: {center: [0.31, 0.2], radius: 0.23}\n'
                        '- box: {center: [-0.4, 0.5], size: [0.5, 0.12], yaw: 0.6}\n'
                        '- regular_polygon: {center: [0.5, -0.6], sides: 5, circumradius: 0.3}\n'
                        '- ring: {center: [0, 0], sides: 6, inner_circumradius: 1.0, outer_circumradius: 1.2}\n')
    raster = rasterize(world, resolution)
    sampled = _supersampled(world, raster, 16)
    # Everything sampling finds is marked; anything marked beyond it is a sliver thinner than
    # the sample spacing, so it lies within one sample spacing of an obstacle.
    assert not (sampled & ~raster.cells).any()
    extra = np.argwhere(raster.cells & ~sampled)
    ox, oy = raster.origin
    centres = np.column_stack([ox + (extra[:, 1] + 0.5) * resolution, oy + (extra[:, 0] + 0.5) * resolution])
    assert (world.distance(centres) <= resolution * (0.5 * math.sqrt(2) + 1 / 16) + 1e-9).all()
    assert len(extra) <= 0.05 * raster.cells.sum()


def test_raster_keeps_thin_walls_and_grid_aligned_edges_exact() -> None:
    world = parse_world('obstacles:\n'
                        '- box: {center: [0.5, 0.5], size: [1.0, 1.0]}\n'        # exactly on grid lines
                        '- box: {center: [2.05, 0.5], size: [0.01, 1.0]}\n'      # a 1 cm shelf board
                        '- segment: {from: [3.0, 0.0], to: [3.0, 1.0]}\n')       # no thickness, on a line
    raster = rasterize(world, 0.1, origin=(0.0, 0.0), size=(12, 35))
    assert raster.cells[:10, :10].all() and not raster.cells[:10, 10].any()     # no spill past x = 1
    assert raster.cells[:10, 20].all() and raster.cells[:10, [19, 21]].sum() == 0
    assert raster.cells[:10, 29].all() and raster.cells[:10, 30].all()          # both sides of x = 3
    assert not raster.cells[10:].any()
    assert raster.cell_of(0.05, 0.05) == (0, 0)
    data = raster.occupancy_data()
    assert data.dtype == np.int8 and set(np.unique(data)) == {0, 100} and data[0] == 100


def _brute_scan(origin, angles, edges, circles, max_range):
    d = np.column_stack([np.cos(angles), np.sin(angles)])
    best = np.full(len(angles), np.inf)
    for x1, y1, x2, y2 in edges:
        ax, ay, ex, ey = x1 - origin[0], y1 - origin[1], x2 - x1, y2 - y1
        with np.errstate(all='ignore'):
            den = d[:, 0] * ey - d[:, 1] * ex
            t, u = (ax * ey - ay * ex) / den, (ax * d[:, 1] - ay * d[:, 0]) / den
        hit = (t >= 0) & (u >= 0) & (u <= 1)
        best[hit] = np.minimum(best[hit], t[hit])
    for cx, cy, r in circles:
        wx, wy = cx - origin[0], cy - origin[1]
        along = d[:, 0] * wx + d[:, 1] * wy
        disc = along ** 2 - (wx * wx + wy * wy - r * r)
        with np.errstate(all='ignore'):
            t = along - np.sqrt(disc)
        hit = (disc >= 0) & (t >= 0)
        best[hit] = np.minimum(best[hit], t[hit])
    best[best > max_range] = np.inf
    return best


@pytest.mark.parametrize('name', ['turtlebot3_world', 'turtlebot3_house', 'turtlebot3_bighouse'])
def test_fan_ray_casting_matches_brute_force(name: str) -> None:
    world = load_world(name)
    rng = np.random.default_rng(7)
    xmin, ymin, xmax, ymax = world.bounds()
    checked = 0
    while checked < 60:
        x, y, yaw = rng.uniform(xmin, xmax), rng.uniform(ymin, ymax), rng.uniform(-4, 4)
        if world.contains([[x, y]])[0]:
            continue
        checked += 1
        got = cast_fan((x, y), yaw, LDS_01.angle_increment, LDS_01.samples, world.edges, world.circles, 3.5)
        want = _brute_scan((x, y), yaw + LDS_01.angles(), world.edges, world.circles, 3.5)
        assert np.array_equal(np.isinf(got), np.isinf(want))
        finite = np.isfinite(got)
        assert np.allclose(got[finite], want[finite], atol=1e-9)
