"""benchmarks/slam.py's `--via` and `--map-from-truth`: a drive through the user's via points, and
the map drawn from the true poses saved in the world frame (what navigation gets when the map's
coverage, not SLAM's pose error, is the question)."""
from __future__ import annotations

import argparse

import numpy as np
import pytest

from benchmarks.slam import _via, run
from zros.map_io import load_map
from zros.sim import load_world

SHORT_DRIVE = [(-2.0, -0.5), (-1.65, -1.65), (0.0, -1.65)]


def test_a_via_point_is_x_comma_y_and_anything_else_one_line():
    assert _via('-2.5,1') == (-2.5, 1.0)
    for bad in ('1', '1,2,3', 'a,b'):
        with pytest.raises(argparse.ArgumentTypeError, match='X,Y'):
            _via(bad)


def test_the_truth_map_follows_the_via_points_and_sits_on_the_true_walls(tmp_path):
    result = run('turtlebot3_world', vias=SHORT_DRIVE, save_map=str(tmp_path / 'truth'), map_from_truth=True)
    assert 2.5 < result['distance_m'] < 5.0                  # the short drive, not the world's loop
    grid = load_map(tmp_path / 'truth.yaml')
    rows, cols = np.nonzero(grid.data == 100)
    centres = (np.stack([cols, rows], axis=1) + 0.5) * grid.resolution + np.asarray(grid.origin[:2])
    near = load_world('turtlebot3_world').distance(centres) <= 2 * grid.resolution
    assert len(centres) > 50 and near.mean() >= 0.97


def test_a_via_point_in_a_wall_is_refused():
    with pytest.raises(ValueError, match='via point'):
        run('turtlebot3_world', vias=[(-2.0, -0.5), (0.0, 0.0)])
