"""nav2_simple_commander's pure tools: LineIterator, PyCostmap2D and FootprintCollisionChecker."""
from __future__ import annotations

import pytest

from zros.nav2_simple_commander.costmap_2d import PyCostmap2D
from zros.nav2_simple_commander.footprint_collision_checker import LETHAL_OBSTACLE, FootprintCollisionChecker
from zros.nav2_simple_commander.line_iterator import LineIterator


def _walk(iterator: LineIterator) -> list[tuple[float, float]]:
    points = []
    while iterator.isValid() and len(points) < 100:
        points.append((iterator.getX(), iterator.getY()))
        iterator.advance()
    return points


def test_steps_follow_the_slope_and_end_on_the_end_point():
    assert _walk(LineIterator(0, 0, 2, -4, 1)) == [(0, 0), (1, -2), (2, -4)]
    assert _walk(LineIterator(3, 1, 3, -1, 1)) == [(3, 1), (3, 0), (3, -1)]       # vertical: along y
    assert _walk(LineIterator(0, 0, 2.5, 0, 1)) == [(0, 0), (1, 0), (2, 0), (2.5, 0)]  # last step clamped
    assert _walk(LineIterator(0, 0, 1, 1, 10)) == [(0, 0), (1, 1)]


def test_length_and_ends():
    line = LineIterator(1, 2, 4, 6)
    assert line.get_line_length() == 5.0
    assert (line.getX0(), line.getY0(), line.getX1(), line.getY1()) == (1, 2, 4, 6)


@pytest.mark.parametrize('args, error', [
    ((0, 0, '1', 1, 1), TypeError), ((0, 0, 1, 1, True), TypeError),
    ((0, 0, 1, 1, 0), ValueError), ((0, 0, 1, 1, -1), ValueError), ((2, 2, 2, 2, 1), ValueError),
])
def test_bad_input_is_refused(args, error):
    with pytest.raises(error):
        LineIterator(*args)


def _grid(width=4, height=3, resolution=0.5, origin=(-1.0, 2.0), data=None):
    from interfaces.nav_msgs.msg import OccupancyGrid
    grid = OccupancyGrid()
    grid.header.frame_id = 'map'
    grid.info.width, grid.info.height, grid.info.resolution = width, height, resolution
    grid.info.origin.position.x, grid.info.origin.position.y = origin
    grid.info.origin.orientation.w = 1.0
    grid.data = data if data is not None else [0] * (width * height)
    return grid


def test_costmap_cells_world_and_unknown_as_255():
    data = [0] * 12
    data[1 * 4 + 2] = -1          # row 1, col 2: unknown
    costmap = PyCostmap2D(_grid(data=data))
    assert (costmap.getSizeInCellsX(), costmap.getSizeInCellsY(), costmap.getGlobalFrameID()) == (4, 3, 'map')
    assert costmap.getCostXY(2, 1) == 255 and costmap.getCostIdx(6) == 255
    assert costmap.mapToWorld(0, 0) == (-0.75, 2.25)
    assert costmap.worldToMapValidated(-0.75, 2.25) == (0, 0)
    assert costmap.worldToMapValidated(0.99, 3.49) == (3, 2)
    assert costmap.worldToMapValidated(1.0, 2.5) == (None, None) == costmap.worldToMapValidated(-1.01, 2.5)
    costmap.setCost(3, 2, 254)
    assert costmap.getCostXY(3, 2) == 254
    with pytest.raises(IndexError):
        costmap.getCostXY(4, 0)


def test_footprint_cost_is_the_highest_cell_under_its_edges_and_lethal_off_the_map():
    from interfaces.geometry_msgs.msg import Point32, Polygon
    data = [0] * 100
    data[5 * 10 + 5] = 90
    checker = FootprintCollisionChecker()
    with pytest.raises(ValueError, match='setCostmap'):
        checker.pointCost(0, 0)
    checker.setCostmap(PyCostmap2D(_grid(10, 10, 1.0, (0.0, 0.0), data)))
    square = Polygon(points=[Point32(x=-0.5, y=-0.5), Point32(x=0.5, y=-0.5), Point32(x=0.5, y=0.5), Point32(x=-0.5, y=0.5)])
    assert checker.footprintCostAtPose(2.0, 2.0, 0.0, square) == 0
    assert checker.footprintCostAtPose(5.2, 5.2, 0.3, square) == 90
    assert checker.footprintCostAtPose(9.8, 5.0, 0.0, square) == LETHAL_OBSTACLE
