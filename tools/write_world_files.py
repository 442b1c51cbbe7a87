"""Write turtlebot3_gazebo's Gazebo world files from zros's YAML worlds (one geometry, two spellings).

    python tools/write_world_files.py            # rewrites nodes/turtlebot3_gazebo/worlds/*.world

Run it after editing a world in zros/sim/worlds/; tests/unit/test_world_files.py checks that
the shipped .world files read back to the YAML worlds.
"""
from __future__ import annotations

import sys
from pathlib import Path

from zros.sim import load_world
from zros.sim.sdf_writer import world_to_sdf

WORLDS = ('empty_world', 'turtlebot3_world', 'turtlebot3_house', 'turtlebot3_bighouse')
OUT = Path(__file__).resolve().parent.parent / 'nodes' / 'turtlebot3_gazebo' / 'worlds'


def main(args: list[str]) -> int:
    OUT.mkdir(exist_ok=True)
    for name in WORLDS:
        text = world_to_sdf(load_world(name), note=f'written by zros (tools/write_world_files.py) from '
                                                   f'zros/sim/worlds/{name}.yaml; edit that file and rerun')
        (OUT / f'{name}.world').write_text(text, encoding='utf-8')
        print(f'{OUT / name}.world')
    return 0


if __name__ == '__main__':
    sys.exit(main(sys.argv[1:]))
