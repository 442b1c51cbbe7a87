"""Write the maps zros's packages ship at upstream's paths, from zros's own worlds.

Courses and Nav2's launch files load `nav2_bringup/maps/turtlebot3_world.yaml` (Humble) and
`nav2_bringup/maps/tb3_sandbox.yaml` (Jazzy; the same TurtleBot3 world under a new name). Both
are maps of turtlebot3_world, so zros makes them from its world file, exactly: the world's
raster (zros.sim.rasterize) on Nav2's grid (384 x 384 cells of 0.05 m, origin (-10, -10)),
walls and pillars occupied, the arena's inside free, and everything a lidar inside could never
see unknown, as a SLAM map leaves it; then zros's map saver writes the files.

Nav2 Jazzy's TurtleBot4 maps, `depot.yaml` and `warehouse.yaml`, are made the same way from
nav2_minimal_tb4_sim's worlds (zros's own depot and warehouse), on upstream's grids. Upstream's
depot map was drawn from the robot's start, so its frame is the world's moved to the spawn point
(-8, 0); the warehouse map is in the world's frame.

    python tools/world_maps.py                      # rewrites the files in nodes/nav2_bringup/maps
    python tools/world_maps.py --out /tmp/maps      # somewhere else
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import NamedTuple

import numpy as np
from scipy import ndimage

from zros.map_io import OccupancyMap, save_map
from zros.sim import load_world, rasterize

__all__ = ['MapSpec', 'MAPS', 'world_map', 'main']

_TB4_WORLDS = Path(__file__).resolve().parents[1] / 'nodes' / 'nav2_minimal_tb4_sim' / 'worlds'


class MapSpec(NamedTuple):
    """A shipped map: the world it shows and its grid. `origin` is in the map's frame, whose
    origin is the world point `frame`; `spawn` (world frame) lies in the free space kept."""
    world: str | Path
    resolution: float
    origin: tuple[float, float]
    size: tuple[int, int]                  # (rows, columns)
    spawn: tuple[float, float]
    frame: tuple[float, float] = (0.0, 0.0)


_TB3 = MapSpec('turtlebot3_world', 0.05, (-10.0, -10.0), (384, 384), (-2.0, -0.5))
#: name of the map file -> what it shows.
MAPS = {'turtlebot3_world': _TB3, 'tb3_sandbox': _TB3,
        'depot': MapSpec(_TB4_WORLDS / 'depot.sdf', 0.05, (-7.14, -7.83), (307, 604), (-8.0, 0.0), (-8.0, 0.0)),
        'warehouse': MapSpec(_TB4_WORLDS / 'warehouse.sdf', 0.03, (-15.1, -25.0), (1674, 1006), (2.12, -21.3))}


def world_map(spec: MapSpec) -> OccupancyMap:
    """The map of a shipped world on its grid: 100 on obstacles, 0 where the robot's spawn
    point connects to, -1 elsewhere."""
    world = load_world(spec.world)
    corner = (spec.origin[0] + spec.frame[0], spec.origin[1] + spec.frame[1])    # in the world
    raster = rasterize(world, spec.resolution, origin=corner, size=spec.size)
    labels, _ = ndimage.label(~raster.cells)
    row = int((spec.spawn[1] - corner[1]) // spec.resolution)
    col = int((spec.spawn[0] - corner[0]) // spec.resolution)
    data = np.full(spec.size, -1, dtype=np.int8)
    data[labels == labels[row, col]] = 0
    data[raster.cells] = 100
    return OccupancyMap(data, spec.resolution, (*spec.origin, 0.0))


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--out', type=Path, default=Path(__file__).resolve().parents[1] / 'nodes' / 'nav2_bringup' / 'maps')
    args = parser.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    for name, spec in MAPS.items():
        yaml_path, _ = save_map(world_map(spec), args.out / name, image_format='png')   # a tenth of pgm's size
        print(yaml_path)
    return 0


if __name__ == '__main__':
    sys.exit(main())
