"""nav2_simple_commander.footprint_collision_checker: the cost a robot footprint would touch.

The footprint's edges are walked cell by cell (LineIterator) on a PyCostmap2D; the highest
cost met is the footprint's, and a footprint that leaves the map is lethal.
"""
from __future__ import annotations

import math
from typing import Any

from zros.nav2_simple_commander.line_iterator import LineIterator

__all__ = ['FootprintCollisionChecker', 'NO_INFORMATION', 'LETHAL_OBSTACLE',
           'INSCRIBED_INFLATED_OBSTACLE', 'MAX_NON_OBSTACLE', 'FREE_SPACE']

NO_INFORMATION = 255
LETHAL_OBSTACLE = 254
INSCRIBED_INFLATED_OBSTACLE = 253
MAX_NON_OBSTACLE = 252
FREE_SPACE = 0


class FootprintCollisionChecker:
    """Costs of points, lines and footprints on the costmap given with `setCostmap`."""

    def __init__(self) -> None:
        self.costmap_ = None

    def setCostmap(self, costmap: Any) -> None:  # noqa: N802 - Nav2's names
        """Use `costmap` (a PyCostmap2D) from now on."""
        self.costmap_ = costmap

    def _costmap(self) -> Any:
        if self.costmap_ is None:
            raise ValueError('no costmap: call setCostmap() first')
        return self.costmap_

    def footprintCost(self, footprint: Any) -> float:  # noqa: N802
        """Highest cost along the closed polygon `footprint` (geometry_msgs/Polygon, world
        coordinates); LETHAL_OBSTACLE when a corner is off the map."""
        costmap = self._costmap()
        cells = [costmap.worldToMapValidated(p.x, p.y) for p in footprint.points]
        if not cells:
            return float(FREE_SPACE)
        if any(x is None for x, _ in cells):
            return float(LETHAL_OBSTACLE)
        cost = 0.0
        for (x0, y0), (x1, y1) in zip(cells, cells[1:] + cells[:1]):
            cost = max(cost, self.lineCost(x0, x1, y0, y1))
            if cost == LETHAL_OBSTACLE:
                break
        return cost

    def lineCost(self, x0: int, x1: int, y0: int, y1: int, step_size: float = 0.5) -> float:  # noqa: N802
        """Highest cost on the cells from (x0, y0) to (x1, y1); IndexError if it leaves the map."""
        if (x0, y0) == (x1, y1):
            return float(self.pointCost(x0, y0))
        line = LineIterator(x0, y0, x1, y1, step_size)
        cost = 0.0
        while line.isValid():
            cost = max(cost, self.pointCost(int(line.getX()), int(line.getY())))
            if cost == LETHAL_OBSTACLE:
                break
            line.advance()
        return cost

    def worldToMapValidated(self, wx: float, wy: float) -> tuple[int | None, int | None]:  # noqa: N802
        """The costmap's cell of a world point, or (None, None) outside it."""
        return self._costmap().worldToMapValidated(wx, wy)

    def pointCost(self, x: int, y: int) -> int:  # noqa: N802
        """Cost of cell (x, y); IndexError outside the map."""
        return self._costmap().getCostXY(x, y)

    def setFootprint(self, footprint: Any) -> None:  # noqa: N802
        self.footprint_ = footprint

    def footprintCostAtPose(self, x: float, y: float, theta: float, footprint: Any) -> float:  # noqa: N802
        """`footprintCost` of `footprint` (robot frame) placed at pose (x, y, theta)."""
        from interfaces.geometry_msgs.msg import Point32, Polygon
        cos, sin = math.cos(theta), math.sin(theta)
        placed = Polygon(points=[Point32(x=x + cos * p.x - sin * p.y, y=y + sin * p.x + cos * p.y, z=p.z)
                                 for p in footprint.points])
        return self.footprintCost(placed)
