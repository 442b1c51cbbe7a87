"""A zros world written as a Gazebo classic world file, so upstream's paths exist for zros's worlds.

    text = world_to_sdf(load_world('turtlebot3_world'), note='from zros/sim/worlds/turtlebot3_world.yaml')

Launch files that students copy from ROBOTIS pass `worlds/turtlebot3_world.world` to gazebo_ros;
turtlebot3_gazebo in zros ships such files, written from the YAML worlds (tools/write_world_files.py)
so there is one geometry and two spellings. Each obstacle becomes a static shape one metre tall
standing on the ground, which zros.sim.sdf cuts back into the same 2D shape at the lidar's height:
a circle an upright `<cylinder>`, a one-loop polygon a `<polyline>`, a ring (two loops, outer and
inner, as turtlebot3_world's wall) one four-cornered `<polyline>` per side, and a zero-thickness
segment a `<box>` a millimetre thick (SDF has no zero-thickness solid). Visuals repeat the
collisions so a real Gazebo shows the same world.
"""
from __future__ import annotations

from xml.sax.saxutils import escape

import numpy as np

from zros.sim.world import World

__all__ = ['world_to_sdf', 'OBSTACLE_HEIGHT', 'SEGMENT_THICKNESS']

OBSTACLE_HEIGHT = 1.0        # [m] every obstacle's height, from the ground up
SEGMENT_THICKNESS = 0.001    # [m] of the box a zero-thickness wall becomes


def world_to_sdf(world: World, *, note: str = '') -> str:
    """SDF 1.6 text of a world file holding `world`'s obstacles as one static model; `note` goes
    into the file's opening comment (where it was written from). ValueError for a polygon zros
    cannot write (several loops that are not a ring's two)."""
    shapes = [_shape(f'circle_{i}', _numbers(cx, cy, OBSTACLE_HEIGHT / 2, 0, 0, 0),
                     f'<cylinder><radius>{_numbers(r)}</radius><length>{_numbers(OBSTACLE_HEIGHT)}</length></cylinder>')
              for i, (cx, cy, r) in enumerate(world.circles)]
    for i, polygon in enumerate(world.polygons):
        for j, loop in enumerate(_convex_or_simple_loops(polygon, i)):
            points = ''.join(f'<point>{_numbers(x, y)}</point>' for x, y in loop)
            shapes.append(_shape(f'polygon_{i}_{j}', '0 0 0 0 0 0',
                                 f'<polyline>{points}<height>{_numbers(OBSTACLE_HEIGHT)}</height></polyline>'))
    for i, (x1, y1, x2, y2) in enumerate(world.segments):
        length, yaw = float(np.hypot(x2 - x1, y2 - y1)), float(np.arctan2(y2 - y1, x2 - x1))
        shapes.append(_shape(f'segment_{i}', _numbers((x1 + x2) / 2, (y1 + y2) / 2, OBSTACLE_HEIGHT / 2, 0, 0, yaw),
                             f'<box><size>{_numbers(length, SEGMENT_THICKNESS, OBSTACLE_HEIGHT)}</size></box>'))
    name = escape(world.name)
    comment = f'<!-- {escape(note)} -->\n' if note else ''
    body = '\n'.join(shapes)
    return (f'<?xml version="1.0"?>\n{comment}<sdf version="1.6">\n<world name="{name}">\n'
            '<include><uri>model://ground_plane</uri></include>\n<include><uri>model://sun</uri></include>\n'
            f'<model name="{name}_obstacles">\n<static>true</static>\n<link name="obstacles">\n{body}\n'
            '</link>\n</model>\n</world>\n</sdf>\n')


def _numbers(*values: float) -> str:
    """Numbers as SDF text, exactly (repr of a float reads back to the same float)."""
    return ' '.join(repr(float(v)) for v in values)


def _shape(name: str, pose: str, geometry: str) -> str:
    return (f'<collision name="{name}"><pose>{pose}</pose><geometry>{geometry}</geometry></collision>'
            f'<visual name="{name}"><pose>{pose}</pose><geometry>{geometry}</geometry></visual>')


def _convex_or_simple_loops(polygon: tuple[np.ndarray, ...], index: int) -> list[np.ndarray]:
    """The loops to write for one area shape: itself if it has one loop, a ring's sides as
    quadrilaterals (outer[k], outer[k+1], inner[k+1], inner[k]) if it has two of equal length."""
    if len(polygon) == 1:
        return [polygon[0]]
    if len(polygon) == 2 and len(polygon[0]) == len(polygon[1]):
        outer, inner = polygon
        nxt = np.roll(np.arange(len(outer)), -1)
        return [np.array([outer[k], outer[nxt[k]], inner[nxt[k]], inner[k]]) for k in range(len(outer))]
    raise ValueError(f'polygon {index} has {len(polygon)} loops: only single loops and rings can be written as SDF')
