"""Write the maps zros's packages ship at upstream's paths, from zros's own worlds.

Courses and Nav2's launch files load `nav2_bringup/maps/turtlebot3_world.yaml` (Humble) and
`nav2_bringup/maps/tb3_sandbox.yaml` (Jazzy; the same TurtleBot3 world under a new name). Both
are maps of turtlebot3_world, so zros makes them from its world file, exactly: the world's
raster (zros.sim.rasterize) on Nav2's grid (384 x 384 cells of 0.05 m, origin (-10, -10)),
walls and pillars occupied, the arena's inside free, and everything a lidar inside could never
see unknown, as a SLAM map leaves it; then zros's map saver writes the files.

    python tools/world_maps.py                      # rewrites the files in nodes/nav2_bringup/maps
    python tools/world_maps.py --out /tmp/maps      # somewhere else
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np
from scipy import ndimage

from zros.map_io import OccupancyMap, save_map
from zros.sim import load_world, rasterize

__all__ = ['world_map', 'main']

#: name of the map file -> world it shows; Nav2's grid for them.
MAPS = {'turtlebot3_world': 'turtlebot3_world', 'tb3_sandbox': 'turtlebot3_world'}
RESOLUTION, ORIGIN, SIZE = 0.05, (-10.0, -10.0), (384, 384)


def world_map(world_name: str) -> OccupancyMap:
    """The map of a shipped world on Nav2's grid: 100 on obstacles, 0 where the robot's spawn
    point connects to, -1 elsewhere."""
    world = load_world(world_name)
    raster = rasterize(world, RESOLUTION, origin=ORIGIN, size=SIZE)
    labels, _ = ndimage.label(~raster.cells)
    row = int((world.spawn.y - ORIGIN[1]) // RESOLUTION)
    col = int((world.spawn.x - ORIGIN[0]) // RESOLUTION)
    data = np.full(SIZE, -1, dtype=np.int8)
    data[labels == labels[row, col]] = 0
    data[raster.cells] = 100
    return OccupancyMap(data, RESOLUTION, (*ORIGIN, 0.0))


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--out', type=Path, default=Path(__file__).resolve().parents[1] / 'nodes' / 'nav2_bringup' / 'maps')
    args = parser.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    for name, world in MAPS.items():
        yaml_path, _ = save_map(world_map(world), args.out / name)
        print(yaml_path)
    return 0


if __name__ == '__main__':
    sys.exit(main())
