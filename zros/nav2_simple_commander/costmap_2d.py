"""nav2_simple_commander.costmap_2d: PyCostmap2D, a costmap message as numpy with Nav2's
Costmap2D accessors (cell <-> world, cost by cell or index).

Built on zros.map_io's view of the OccupancyGrid and its GridGeometry (the one world <-> cell
rule of zros). Costs are the message's cells as unsigned bytes, as Nav2 reads them: -1
(unknown) is 255, a lethal obstacle 254.
"""
from __future__ import annotations

from typing import Any

import numpy as np

from zros.map_io import map_from_msg

__all__ = ['PyCostmap2D']


class PyCostmap2D:
    """Nav2's Python costmap over a nav_msgs/OccupancyGrid (or a nav2_msgs/Costmap's grid).

    :param occupancy_map: the grid message; its cells are copied.
    :raises ValueError: when the data does not hold width x height cells.
    """

    def __init__(self, occupancy_map: Any) -> None:
        grid = map_from_msg(occupancy_map)
        self.geometry = grid.geometry
        self.size_x, self.size_y = grid.width, grid.height
        self.resolution = grid.resolution
        self.origin_x, self.origin_y = grid.origin[0], grid.origin[1]
        self.global_frame_id = occupancy_map.header.frame_id
        self.costmap_timestamp = occupancy_map.header.stamp
        self.costmap = grid.data.reshape(-1).view(np.uint8).copy()   # row-major, as the message

    def getSizeInCellsX(self) -> int:  # noqa: N802 - Nav2's names
        """Width [cells]."""
        return self.size_x

    def getSizeInCellsY(self) -> int:  # noqa: N802
        """Height [cells]."""
        return self.size_y

    def getSizeInMetersX(self) -> float:  # noqa: N802
        """Width [m], by Nav2's formula: (cells - 0.5) * resolution."""
        return (self.size_x - 1 + 0.5) * self.resolution

    def getSizeInMetersY(self) -> float:  # noqa: N802
        return (self.size_y - 1 + 0.5) * self.resolution

    def getOriginX(self) -> float:  # noqa: N802
        return self.origin_x

    def getOriginY(self) -> float:  # noqa: N802
        return self.origin_y

    def getResolution(self) -> float:  # noqa: N802
        return self.resolution

    def getGlobalFrameID(self) -> str:  # noqa: N802
        return self.global_frame_id

    def getCostmapTimestamp(self) -> Any:  # noqa: N802
        return self.costmap_timestamp

    def getCostXY(self, mx: int, my: int) -> int:  # noqa: N802
        """Cost of cell (mx, my); IndexError outside the map."""
        return int(self.costmap[self.getIndex(mx, my)])

    def getCostIdx(self, index: int) -> int:  # noqa: N802
        return int(self.costmap[index])

    def setCost(self, mx: int, my: int, cost: int) -> None:  # noqa: N802
        self.costmap[self.getIndex(mx, my)] = cost

    def mapToWorld(self, mx: int, my: int) -> tuple[float, float]:  # noqa: N802
        """World (x, y) [m] of the centre of cell (mx, my)."""
        x, y = self.geometry.cell_centre(my, mx)
        return float(x), float(y)

    def worldToMapValidated(self, wx: float, wy: float) -> tuple[int | None, int | None]:  # noqa: N802
        """The cell (mx, my) holding world point (wx, wy), or (None, None) outside the map."""
        row, col = self.geometry.world_to_cell(wx, wy)
        if not self.geometry.contains(row, col):
            return None, None
        return int(col), int(row)

    def getIndex(self, mx: int, my: int) -> int:  # noqa: N802
        """Row-major index of cell (mx, my); IndexError outside the map."""
        if not (0 <= mx < self.size_x and 0 <= my < self.size_y):
            raise IndexError(f'cell ({mx}, {my}) is outside the {self.size_x} x {self.size_y} costmap')
        return int(self.geometry.index(my, mx))
