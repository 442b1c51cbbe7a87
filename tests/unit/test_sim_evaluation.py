"""The SLAM map metrics and their picture (zros.sim.evaluation): what a perfect map scores, what a
map offset by a few centimetres scores, and that the overlay paints exactly what is counted."""
from __future__ import annotations

import numpy as np

from zros.map_io import OccupancyMap
from zros.sim.evaluation import OVERLAY_COLOURS, edge_errors, ground_truth_map, map_quality, overlay
from zros.sim.raster import rasterize
from zros.sim.world import Pose2D, World, box_loop


def room() -> World:
    """A 4 m x 3 m room of 0.15 m walls whose faces fall between the 5 cm grid lines (as the house's do)."""
    walls = [box_loop(0.013, 1.5, 0.15, 3.15), box_loop(4.013, 1.5, 0.15, 3.15),
             box_loop(2.013, 0.0, 4.15, 0.15), box_loop(2.013, 3.0, 4.15, 0.15)]
    return World('room', spawn=Pose2D(2.0, 1.5, 0.0), polygons=tuple((loop,) for loop in walls))


def seen(truth, world_map: OccupancyMap) -> np.ndarray:
    """The wall faces a robot inside sees: the truth cells the perfect map marks occupied."""
    centres = truth.geometry
    rows, cols = np.nonzero(truth.cells)
    x, y = centres.origin[0] + (cols + 0.5) * truth.resolution, centres.origin[1] + (rows + 0.5) * truth.resolution
    r = np.floor((y - world_map.origin[1]) / world_map.resolution).astype(int)
    c = np.floor((x - world_map.origin[0]) / world_map.resolution).astype(int)
    ok = (r >= 0) & (r < world_map.data.shape[0]) & (c >= 0) & (c < world_map.data.shape[1])
    walls = np.zeros(truth.cells.shape, dtype=bool)
    walls[rows[ok], cols[ok]] = world_map.data[r[ok], c[ok]] == 100
    return walls


def room_maps() -> tuple:
    """The room's truth raster, its perfect 5 cm map, and the wall cells a robot inside sees."""
    world = room()
    truth = rasterize(world, 0.05)
    perfect = ground_truth_map(world, 0.05)
    return truth, perfect, seen(truth, perfect)


def test_a_perfect_map_scores_perfectly_and_shows_no_red():
    truth, perfect, walls = room_maps()
    quality = map_quality(perfect, np.zeros(3), truth, walls)
    assert quality.wall_recall == 1.0 and quality.false_occupied == 0.0 and quality.wall_cells > 200
    assert quality.false_occupied_beyond_one_cell == 0.0
    picture = overlay(perfect, np.zeros(3), truth, walls, scale=1)
    assert picture.shape == (*truth.cells.shape, 3) and picture.dtype == np.uint8
    red = (picture == OVERLAY_COLOURS['false_occupied']).all(axis=2)
    black = (picture == OVERLAY_COLOURS['wall_found']).all(axis=2)
    assert not red.any() and black.sum() == quality.wall_cells


def test_a_map_in_another_frame_scores_the_same_once_the_frame_is_given():
    truth, perfect, walls = room_maps()
    spawn = np.array([2.0, 1.5, 0.0])                  # SLAM's map frame: where the robot started
    ox, oy, _ = perfect.origin
    in_map = OccupancyMap(perfect.data, perfect.resolution, (ox - 2.0, oy - 1.5, 0.0))
    assert map_quality(in_map, spawn, truth, walls) == map_quality(perfect, np.zeros(3), truth, walls)


def test_a_map_two_cells_off_is_counted_and_painted_where_it_is_wrong():
    truth, perfect, walls = room_maps()
    ox, oy, _ = perfect.origin
    shifted = OccupancyMap(perfect.data, perfect.resolution, (ox + 0.1, oy, 0.0))     # 10 cm east
    quality = map_quality(shifted, np.zeros(3), truth, walls)
    # The west and east faces land two cells off (the east one inside its 3-cell wall, the west
    # one in the room); the north and south walls slide along themselves.
    assert 0.05 < quality.false_occupied < 0.3 and quality.wall_recall < 1.0
    assert 0.0 < quality.false_occupied_beyond_one_cell <= quality.false_occupied
    picture = overlay(shifted, np.zeros(3), truth, walls, scale=1)[::-1]      # back to row 0 = lowest y
    red = (picture == OVERLAY_COLOURS['false_occupied']).all(axis=2)
    assert red.sum() == round(quality.false_occupied * quality.occupied_cells)
    red_x = truth.origin[0] + (np.nonzero(red)[1] + 0.5) * truth.resolution
    assert ((red_x > 0.05) & (red_x < 0.3)).all()          # just inside the west wall's face (x = 0.088)
    assert (picture == OVERLAY_COLOURS['wall_missed']).all(axis=2).any()


def test_a_wall_one_cell_thick_in_front_of_its_face_is_false_only_to_the_strict_count():
    """What lidar noise does to a face on a grid line: the free cell in front is marked too."""
    truth, perfect, walls = room_maps()
    ox, oy, _ = perfect.origin
    one_off = OccupancyMap(perfect.data, perfect.resolution, (ox + 0.05, oy, 0.0))
    quality = map_quality(one_off, np.zeros(3), truth, walls)
    assert quality.false_occupied > 0.02 and quality.false_occupied_beyond_one_cell == 0.0


def test_edge_errors_measure_each_edge_against_the_true_relative_pose():
    truth = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, np.pi / 2], [1.0, 1.0, np.pi]])
    # 0 -> 1 right; 1 -> 2 says 2 is 0.9 m ahead of 1 (truly 1 m) and turned 0.1 rad too far.
    error = edge_errors(np.array([0, 1]), np.array([1, 2]),
                        np.array([[1.0, 0.0, np.pi / 2], [0.9, 0.0, np.pi / 2 + 0.1]]), truth)
    assert np.allclose(error, [[0.0, 0.0], [0.1, 0.1]])
