"""zros.sim.sdf: Gazebo world files cut at the lidar's height, without processes.

Small SDF files written here: a box room, upright and lying cylinders, a sphere, a model folder
included through `model://` with its pose overridden, nested poses, a mesh made with trimesh,
and the one-line errors. (ROBOTIS's own world files are checked by hand: docs/robot.md.)
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from zros.sim import load_world
from zros.sim.sdf import SdfError, find_model, parse_sdf_world, pose_matrix


def sdf(body: str) -> str:
    return f'<?xml version="1.0"?>\n<sdf version="1.6">\n<world name="test">\n{body}\n</world>\n</sdf>\n'


def box_model(name: str, pose: str, size: str, *, static: bool = True) -> str:
    return (f'<model name="{name}"><static>{int(static)}</static><pose>{pose}</pose><link name="l">'
            f'<collision name="c"><geometry><box><size>{size}</size></box></geometry></collision>'
            f'<visual name="v"><geometry><box><size>9 9 9</size></box></geometry></visual></link></model>')


def test_a_box_room_is_four_wall_rectangles_and_the_ground_plane_is_left_out() -> None:
    walls = ''.join(box_model(f'w{i}', pose, size) for i, (pose, size) in enumerate([
        ('0 2 0.5 0 0 0', '4 0.1 1'), ('0 -2 0.5 0 0 0', '4 0.1 1'),
        ('2 0 0.5 0 0 1.5707963', '4 0.1 1'), ('-2 0 0.5 0 0 1.5707963', '4 0.1 1')]))
    ground = ('<model name="ground"><static>1</static><link name="l"><collision name="c"><geometry><plane>'
              '<normal>0 0 1</normal><size>100 100</size></plane></geometry></collision></link></model>')
    world = parse_sdf_world(sdf(walls + ground))
    assert world.name == 'test'
    assert len(world.polygons) == 4 and len(world.circles) == 0
    assert world.bounds() == pytest.approx((-2.05, -2.05, 2.05, 2.05), abs=1e-6)
    inside = world.contains(np.array([[0.0, 2.0], [2.0, 0.0], [0.0, 0.0], [1.0, 1.0]]))
    assert inside.tolist() == [True, True, False, False]
    assert world.distance(np.array([[0.0, 0.0]]))[0] == pytest.approx(1.95)     # the visual is not collision


def test_shapes_the_plane_misses_are_left_out_and_tilted_ones_are_cut_exactly() -> None:
    shapes = (box_model('low', '5 5 0.05 0 0 0', '1 1 0.1')                    # below 0.18 m
              + box_model('high', '5 5 1.0 0 0 0', '1 1 0.2')                  # above
              + box_model('tilted', '0 0 0.18 0 0.7853982 0', '1 1 1'))        # pitched 45 degrees
    world = parse_sdf_world(sdf(shapes))
    assert len(world.polygons) == 1
    loop, = world.polygons[0]
    # A unit cube pitched 45 degrees about y, cut through its centre: x spans +-sqrt(2)/2, y +-0.5.
    assert loop[:, 0].min() == pytest.approx(-math.sqrt(0.5), abs=1e-6)
    assert loop[:, 0].max() == pytest.approx(math.sqrt(0.5), abs=1e-6)
    assert loop[:, 1].max() == pytest.approx(0.5, abs=1e-6)


def test_cylinders_and_spheres() -> None:
    def shape(name: str, pose: str, geometry: str) -> str:
        return (f'<model name="{name}"><static>1</static><link name="l"><pose>{pose}</pose><collision name="c">'
                f'<geometry>{geometry}</geometry></collision></link></model>')
    world = parse_sdf_world(sdf(
        shape('pillar', '1 2 0.25 0 0 0', '<cylinder><radius>0.15</radius><length>0.5</length></cylinder>')
        + shape('ball', '-1 0 0.3 0 0 0', '<sphere><radius>0.2</radius></sphere>')
        + shape('pipe', '0 -2 0.18 1.5707963 0 0', '<cylinder><radius>0.1</radius><length>2</length></cylinder>')))
    assert world.circles[0] == pytest.approx([1.0, 2.0, 0.15])
    assert world.circles[1] == pytest.approx([-1.0, 0.0, math.sqrt(0.2 ** 2 - 0.12 ** 2)])
    loop, = world.polygons[0]         # the pipe lies along y: a 0.2 x 2 m rectangle
    assert np.ptp(loop[:, 0]) == pytest.approx(0.2, abs=1e-3) and np.ptp(loop[:, 1]) == pytest.approx(2.0, abs=1e-6)


def write_model(folder: Path, name: str, body: str) -> Path:
    model = folder / name
    model.mkdir(parents=True)
    (model / 'model.config').write_text(f'<?xml version="1.0"?><model><name>{name}</name>'
                                        '<sdf version="1.5">model-old.sdf</sdf><sdf version="1.6">model.sdf</sdf></model>')
    (model / 'model.sdf').write_text(f'<?xml version="1.0"?><sdf version="1.6">{body}</sdf>')
    (model / 'model-old.sdf').write_text('<sdf version="1.5"><model name="old"/></sdf>')
    return model


def test_includes_resolve_on_the_model_path_with_nested_poses(tmp_path: Path) -> None:
    # A model whose link sits 1 m along its x, and whose box sits 0.5 m further along the link's x.
    inner = ('<model name="post"><pose>9 9 0 0 0 0</pose><link name="l"><pose>1 0 0 0 0 0</pose>'
             '<collision name="c"><pose>0.5 0 0.5 0 0 0</pose><geometry><box><size>0.2 0.2 1</size></box>'
             '</geometry></collision></link></model>')
    write_model(tmp_path / 'models', 'post', inner)
    assert find_model('post', [tmp_path / 'models']) == tmp_path / 'models' / 'post'
    # Included into a static model turned 90 degrees at (2, 0): the include's pose replaces 9 9 0.
    text = sdf('<model name="outer"><static>1</static><pose>2 0 0 0 0 1.5707963</pose>'
               '<include><uri>model://post</uri><pose>0 1 0 0 0 0</pose></include></model>'
               '<include><uri>model://ground_plane</uri></include><include><uri>model://sun</uri></include>')
    warnings: list[str] = []
    world = parse_sdf_world(text, model_path=[tmp_path / 'models'], on_warning=warnings.append)
    assert warnings == []
    loop, = world.polygons[0]
    # outer: (2, 0) yaw 90; include: (0, 1) in it -> (1, 0); link +1 in x -> +1 in world y; box +0.5.
    assert loop.mean(axis=0) == pytest.approx([1.0, 1.5], abs=1e-6)


def test_a_missing_model_or_mesh_is_left_out_with_one_warning_each(tmp_path: Path) -> None:
    text = sdf('<include><uri>model://nowhere</uri></include>'
               '<model name="m"><link name="l"><collision name="c"><geometry><mesh><uri>model://gone/x.dae</uri>'
               '</mesh></geometry></collision></link></model>')
    warnings: list[str] = []
    world = parse_sdf_world(text, source=tmp_path / 'w.world', model_path=[tmp_path], on_warning=warnings.append)
    assert world.is_empty
    assert len(warnings) == 2
    assert warnings[0].startswith(f'{tmp_path / "w.world"}:4: model ') and "'model://nowhere'" in warnings[0]
    assert "mesh 'model://gone/x.dae' not found" in warnings[1]


def test_a_mesh_is_cut_into_wall_segments(tmp_path: Path) -> None:
    trimesh = pytest.importorskip('trimesh')
    ring = trimesh.creation.annulus(r_min=1.0, r_max=1.2, height=1.0, sections=24)   # centred on z = 0
    model = tmp_path / 'models' / 'ring'
    (model / 'meshes').mkdir(parents=True)
    ring.export(model / 'meshes' / 'ring.stl')
    (model / 'model.sdf').write_text(
        '<sdf version="1.6"><model name="ring"><static>1</static><link name="l"><collision name="c">'
        '<pose>3 0 0.5 0 0 0</pose><geometry><mesh><uri>model://ring/meshes/ring.stl</uri><scale>2 2 1</scale>'
        '</mesh></geometry></collision></link></model></sdf>')
    world = parse_sdf_world(sdf('<include><uri>model://ring</uri></include>'), model_path=[tmp_path / 'models'])
    assert len(world.segments) == 96          # 24 sides outside, 24 inside, each two triangles
    radii = np.hypot(world.segments[:, 0] - 3.0, world.segments[:, 1])
    assert radii.max() == pytest.approx(2.4, abs=1e-6) and radii.min() == pytest.approx(2.0, abs=1e-6)


def test_load_world_takes_world_files_by_suffix(tmp_path: Path) -> None:
    path = tmp_path / 'room.world'
    path.write_text(sdf(box_model('w', '0 1 0.5 0 0 0', '2 0.1 1')))
    world = load_world(path)
    assert world.source == path and len(world.polygons) == 1


@pytest.mark.parametrize('text, message', [
    (sdf('<model name="m"><link name="l">'), ':5: invalid XML: '),
    (sdf('<model name="m"><pose>1 2 3</pose></model>'), ":4: <pose> needs 6 finite numbers, got '1 2 3'"),
    (sdf('<model name="m"><link name="l"><collision name="c"><geometry><cylinder><radius>0</radius>'
         '<length>1</length></cylinder></geometry></collision></link></model>'), ':4: <radius> must be > 0, got 0'),
    ('<robot name="r"/>', ':1: expected an <sdf> document, got <robot>'),
    (sdf('<model name="m"><static>yes</static></model>'), ":4: <static> must be true or false, got 'yes'"),
    (sdf('<model name="m"><link name="l"><inertial><mass>0</mass></inertial><collision name="c"><geometry><box>'
         '<size>1 1 1</size></box></geometry></collision></link></model>'), ':4: <mass> must be > 0, got 0'),
])
def test_bad_files_are_one_line_errors_naming_file_and_line(text: str, message: str) -> None:
    with pytest.raises(SdfError) as caught:
        parse_sdf_world(text, source='my.world')
    assert str(caught.value).startswith('my.world:') and message in str(caught.value)
    assert '\n' not in str(caught.value)


def test_pose_matrix_is_roll_then_pitch_then_yaw_about_fixed_axes() -> None:
    matrix = pose_matrix(1, 2, 3, math.pi / 2, 0, math.pi / 2)
    # x -> (yaw 90) y;  z -> (roll 90) -y -> (yaw 90) x.
    assert matrix[:3, :3] @ [1, 0, 0] == pytest.approx([0, 1, 0], abs=1e-12)
    assert matrix[:3, :3] @ [0, 0, 1] == pytest.approx([1, 0, 0], abs=1e-12)
    assert matrix[:3, 3].tolist() == [1, 2, 3]


def test_non_static_models_are_pushable_bodies_with_their_mass_unless_inside_a_static_one() -> None:
    loose = box_model('crate', '1 0 0.1 0 0 0', '0.2 0.2 0.2', static=False).replace(
        '<link name="l">', '<link name="l"><inertial><mass>0.4</mass></inertial>')
    no_flag = box_model('bin', '0 2 0.5 0 0 0', '0.3 0.3 1').replace('<static>1</static>', '')   # SDF: not static
    held = ('<model name="shelf"><static>true</static>'
            + box_model('drawer', '0 -2 0.5 0 0 0', '0.3 0.3 1', static=False) + '</model>')
    world = parse_sdf_world(sdf(loose + no_flag + held))
    assert [(b.name, b.mass) for b in world.bodies] == [('crate', 0.4), ('bin', 1.0)]
    crate = world.bodies[0].polygons[0]
    assert np.allclose(sorted(map(tuple, crate)), [(0.9, -0.1), (0.9, 0.1), (1.1, -0.1), (1.1, 0.1)])
    # The bodies are not fixed obstacles; the drawer, inside a static model, is.
    assert len(world.polygons) == 1 and world.contains(np.array([[0.0, -2.0]]))[0]
    assert not world.contains(np.array([[1.0, 0.0], [0.0, 2.0]])).any()
