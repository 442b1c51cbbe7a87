"""Map files by nav2_map_server's rules (zros.map_io): files written by hand as ROS writes them
load as ROS loads them, trinary maps round-trip byte for byte, bad files fail with one line naming
the file and key, and the shipped turtlebot3_world map is the world's exact raster."""
from __future__ import annotations

import math

import numpy as np
import pytest

from conftest import REPO
from zros.map_io import (MapFileError, MapImageError, MapMetadataError, MapNotFoundError, OccupancyMap, load_map,
                         map_from_msg, map_to_msg, read_map_yaml, save_map)
from zros.image_io import encode_png

ROS_YAML = """image: {image}
mode: {mode}
resolution: 0.050000
origin: [-1.000000, -2.500000, 0.000000]
negate: {negate}
occupied_thresh: 0.65
free_thresh: 0.25
"""


def write_ros_map(tmp_path, pixels: np.ndarray, *, mode: str = 'trinary', negate: int = 0, ascii: bool = False):
    """A map as map_saver writes it: P5 (or P2) greyscale, top row first, and its YAML."""
    height, width = pixels.shape
    if ascii:
        body = ('P2\n# a comment\n' + f'{width} {height}\n255\n' + '\n'.join(' '.join(map(str, row)) for row in pixels))
        (tmp_path / 'ros.pgm').write_text(body)
    else:
        (tmp_path / 'ros.pgm').write_bytes(f'P5\n# CREATOR: map_saver.cpp 0.050 m/pix\n{width} {height}\n255\n'.encode()
                                           + pixels.astype(np.uint8).tobytes())
    (tmp_path / 'ros.yaml').write_text(ROS_YAML.format(image='ros.pgm', mode=mode, negate=negate))
    return tmp_path / 'ros.yaml'


def test_a_map_written_by_ros_rules_loads_as_nav2_loads_it(tmp_path):
    # Top row first in the file: free, occupied, map_saver's unknown grey 205 (occupancy 0.196:
    # below nav2's free_thresh 0.25, so free, as nav2 reads it), a light grey, a mid grey (0.5: unknown).
    pixels = np.array([[254, 0, 205, 204, 128],
                       [0, 0, 254, 254, 254]], dtype=np.uint8)
    grid = load_map(write_ros_map(tmp_path, pixels))
    assert grid.resolution == 0.05 and grid.origin == (-1.0, -2.5, 0.0)
    # The image's top row is the grid's last row (highest y).
    assert grid.data.tolist() == [[100, 100, 0, 0, 0], [0, 100, 0, 0, -1]]
    assert load_map(write_ros_map(tmp_path, pixels, ascii=True)).data.tolist() == grid.data.tolist()
    # negate: dark is free.
    assert load_map(write_ros_map(tmp_path, pixels, negate=1)).data.tolist() == [[0, 0, 100, 100, 100],
                                                                                   [100, 0, 100, 100, -1]]
    # scale: graded between the thresholds, rint(100 (occ - free) / (occupied - free)).
    scaled = load_map(write_ros_map(tmp_path, pixels, mode='scale')).data
    assert scaled[1, 4] == round(100 * ((1 - 128 / 255) - 0.25) / 0.4) and scaled[1, 2] == 0
    # raw: the pixel value is the cell value when within 0..100, else unknown.
    raw = load_map(write_ros_map(tmp_path, np.array([[0, 55, 100, 101, 255]], dtype=np.uint8), mode='raw')).data
    assert raw.tolist() == [[0, 55, 100, -1, -1]]


def test_numbers_in_exponent_form_read_as_yaml_cpp_reads_them(tmp_path):
    """`1e-05` and `5E-2` are numbers to nav2 (yaml-cpp) but strings to YAML 1.1; save_map writes
    a tiny origin that way (found by tests/unit/test_round_trips.py)."""
    write_ros_map(tmp_path, np.array([[254]], dtype=np.uint8))
    text = (tmp_path / 'ros.yaml').read_text()
    (tmp_path / 'ros.yaml').write_text(text.replace('resolution: 0.050000', 'resolution: 5E-2')
                                       .replace('[-1.000000, -2.500000, 0.000000]', '[1e-05, -2.5e1, 0]'))
    grid = load_map(tmp_path / 'ros.yaml')
    assert grid.resolution == 0.05 and grid.origin == (1e-05, -25.0, 0.0)
    tiny = OccupancyMap(np.zeros((1, 1), dtype=np.int8), 1.0, (0.0, 0.0, 1e-300))
    assert load_map(save_map(tiny, tmp_path / 'tiny')[0]).origin == (0.0, 0.0, 1e-300)


def test_scale_mode_png_transparency_is_unknown(tmp_path):
    rgba = np.zeros((1, 3, 4), dtype=np.uint8)
    rgba[0, :, :3] = [[255, 255, 255], [0, 0, 0], [128, 128, 128]]
    rgba[0, :, 3] = [255, 255, 0]
    (tmp_path / 'm.png').write_bytes(encode_png(rgba))
    (tmp_path / 'm.yaml').write_text(ROS_YAML.format(image='m.png', mode='scale', negate='false'))
    assert load_map(tmp_path / 'm.yaml').data.tolist() == [[0, 100, -1]]


def test_trinary_round_trip_is_byte_for_byte(tmp_path):
    rng = np.random.default_rng(3)
    data = rng.choice(np.array([-1, 0, 100], dtype=np.int8), size=(37, 52))
    grid = OccupancyMap(data, 0.05, (-12.35, 3.0, 0.0))
    yaml_path, image_path = save_map(grid, tmp_path / 'first')
    header = 'P5\n# CREATOR: map_saver.cpp 0.050 m/pix\n52 37\n255\n'.encode()
    assert image_path.read_bytes().startswith(header)
    assert set(np.unique(np.frombuffer(image_path.read_bytes()[len(header):], np.uint8))) == {0, 205, 254}
    assert read_map_yaml(yaml_path).origin == (-12.35, 3.0, 0.0)
    loaded = load_map(yaml_path)
    assert np.array_equal(loaded.data, data) and loaded.origin == grid.origin and loaded.resolution == 0.05
    yaml_again, image_again = save_map(loaded, tmp_path / 'first_again')
    assert image_again.read_bytes() == image_path.read_bytes()
    assert yaml_again.read_text() == yaml_path.read_text().replace('first.pgm', 'first_again.pgm')


def test_save_modes_and_thresholds(tmp_path):
    data = np.array([[-1, 0, 19, 20, 64, 65, 100]], dtype=np.int8)
    _, image = save_map(OccupancyMap(data, 0.1, (0.0, 0.0, 0.0)), tmp_path / 't', free_thresh=0.196)
    assert list(image.read_bytes()[-7:]) == [205, 254, 254, 254, 205, 0, 0]
    _, image = save_map(OccupancyMap(data, 0.1, (0.0, 0.0, 0.0)), tmp_path / 'r', mode='raw')
    assert list(image.read_bytes()[-7:]) == [255, 0, 19, 20, 64, 65, 100]
    yaml_path, image = save_map(OccupancyMap(data, 0.1, (0.0, 0.0, 0.0)), tmp_path / 's', mode='scale')
    assert image.suffix == '.png' and 'mode: scale' in yaml_path.read_text()
    back = load_map(yaml_path).data
    assert back[0, 0] == -1 and back[0, 1] == 0 and back[0, 6] == 100
    with pytest.raises(MapFileError, match='pgm'):
        save_map(OccupancyMap(data, 0.1, (0.0, 0.0, 0.0)), tmp_path / 'x', mode='scale', image_format='pgm')


@pytest.mark.parametrize('yaml_text, error, fragment', [
    ('image: nothere.pgm\nresolution: 0.05\norigin: [0, 0, 0]\noccupied_thresh: 0.65\nfree_thresh: 0.25\n',
     MapImageError, 'nothere.pgm'),
    ('image: m.pgm\nresolution: 0.05\norigin: [0, 0]\noccupied_thresh: 0.65\nfree_thresh: 0.25\n',
     MapMetadataError, 'origin: must have 3 elements'),
    ('image: m.pgm\nresolution: 0.05\norigin: [0, 0, 0]\noccupied_thresh: 0.65\nfree_thresh: 0.25\nmode: fancy\n',
     MapMetadataError, "mode: unsupported 'fancy'"),
    ('image: m.pgm\nresolution: fine\norigin: [0, 0, 0]\noccupied_thresh: 0.65\nfree_thresh: 0.25\n',
     MapMetadataError, 'resolution: must be a number'),
    ('image: m.pgm\norigin: [0, 0, 0]\noccupied_thresh: 0.65\nfree_thresh: 0.25\n',
     MapMetadataError, 'resolution: missing'),
    ('image: [m.pgm\n', MapMetadataError, 'not valid YAML'),
])
def test_bad_map_files_name_the_file_and_key(tmp_path, yaml_text, error, fragment):
    (tmp_path / 'm.pgm').write_bytes(b'P5\n1 1\n255\n\xfe')
    (tmp_path / 'bad.yaml').write_text(yaml_text)
    with pytest.raises(error) as caught:
        load_map(tmp_path / 'bad.yaml')
    text = str(caught.value)
    assert fragment in text and str(tmp_path / 'bad.yaml') in text and '\n' not in text
    with pytest.raises(MapNotFoundError, match='cannot read'):
        load_map(tmp_path / 'missing.yaml')


def test_occupancy_grid_message_round_trip():
    grid = OccupancyMap(np.arange(-1, 11, dtype=np.int8).reshape(3, 4), 0.1, (1.5, -2.0, 0.5))
    msg = map_to_msg(grid, frame_id='map')
    assert (msg.info.width, msg.info.height) == (4, 3) and msg.header.frame_id == 'map'
    back = map_from_msg(msg)
    assert np.array_equal(back.data, grid.data) and back.resolution == pytest.approx(0.1)
    assert back.origin[:2] == (1.5, -2.0) and math.isclose(back.origin[2], 0.5)


def test_shipped_turtlebot3_world_map_is_the_worlds_exact_raster():
    from scipy import ndimage
    from zros.sim import load_world, rasterize
    grid = load_map(REPO / 'nodes' / 'turtlebot3_navigation2' / 'map' / 'map.yaml')
    assert grid.resolution == 0.05 and grid.origin[2] == 0.0
    raster = rasterize(load_world('turtlebot3_world'), 0.05, origin=grid.origin[:2],
                       size=(grid.height, grid.width)).cells
    free, occupied = grid.data == 0, grid.data == 100
    assert not (free & raster).any() and not (occupied & ~raster).any()
    # Every obstacle cell that touches the free space is marked occupied: the walls as the lidar sees them.
    touching = raster & ndimage.binary_dilation(free, structure=np.ones((3, 3), dtype=bool))
    assert np.array_equal(touching, occupied)

    def cell(x, y):
        return grid.data[int((y - grid.origin[1]) / grid.resolution), int((x - grid.origin[0]) / grid.resolution)]
    # The robot's spawn point is free; the centre pillar and the wall (inside at y = 2.54) are
    # occupied; behind the wall is unknown.
    assert cell(-2.0, -0.5) == 0 and cell(0.0, 0.14) == 100 and cell(0.0, 2.52) == 100 and cell(0.0, 2.65) == -1
    # ... and it is what the documented generator makes.
    from zros.sim.evaluation import ground_truth_map
    made = ground_truth_map(load_world('turtlebot3_world'))
    assert np.array_equal(made.data, grid.data) and made.origin == grid.origin


def test_course_goals_amcls_initial_pose_and_the_simulators_odometry_share_the_maps_frame():
    """The shipped map is in the world frame; the simulator's odometry (Gazebo's world source)
    starts at the spawn pose, so seed 000's navigation_from_text (initial pose := the odometry
    pose) gives AMCL (-2.0, -0.5), and the goals of goals.txt are free space of the same map."""
    from zros.sim import Simulation, load_world
    world = load_world('turtlebot3_world')
    robot = Simulation(world).add_robot('burger', (-2.0, -0.5, 0.0))
    odom = robot.odometry()
    assert (odom.x, odom.y, odom.yaw) == (-2.0, -0.5, 0.0)
    grid = load_map(REPO / 'nodes' / 'turtlebot3_navigation2' / 'map' / 'map.yaml')
    goals = [tuple(map(float, line.split()[:2]))
             for line in (REPO / 'nodes' / 'navigation_from_text' / 'goals.txt').read_text().splitlines() if line.strip()]
    assert len(goals) == 3
    for x, y in [(odom.x, odom.y), *goals]:
        col, row = int((x - grid.origin[0]) / grid.resolution), int((y - grid.origin[1]) / grid.resolution)
        assert grid.data[row, col] == 0, (x, y)
        assert world.distance(np.array([[x, y]]))[0] > 0.2, (x, y)    # room for the burger (0.105 m)
