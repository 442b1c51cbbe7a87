"""World files: a world's obstacles as YAML (or JSON) a user can read, copy and edit.

    name: my_world
    spawn: {x: -2.0, y: -0.5, yaw: 0.0}      # where a robot starts unless told otherwise
    obstacles:                               # metres and radians, Gazebo's world frame
    - circle: {center: [0.0, 0.0], radius: 0.15}
    - box: {center: [1.0, 2.0], size: [4.5, 0.15], yaw: 1.5708}   # size[0] lies along yaw
    - polygon: {points: [[0, 0], [1, 0], [0.5, 1]]}
    - regular_polygon: {center: [1.8, 2.7], sides: 6, circumradius: 0.8066, rotation: 0.0}
    - ring: {center: [0, 0], sides: 6, inner_circumradius: 2.93, outer_circumradius: 3.30}
    - segment: {from: [0, 0], to: [2, 0]}   # a wall of no thickness

`rotation` is the angle of the first corner from +x (0 puts a corner on the +x axis). A bad
file is refused with its path, line and key: `my_world.yaml:7: obstacles[2].circle.radius:
must be > 0 (got -0.1)`. The worlds shipped with zros (`empty_world`, `turtlebot3_world`,
`turtlebot3_house`) are in `WORLDS_DIR` and load by name.
"""
from __future__ import annotations

import math
import os
from pathlib import Path
from typing import Any, Callable

import numpy as np
import yaml

from zros.errors import ZrosError
from zros.sim.world import Pose2D, World, box_loop, regular_polygon_loop

__all__ = ['WorldFileError', 'load_world', 'parse_world', 'world_names', 'world_path', 'WORLDS_DIR']

WORLDS_DIR = Path(__file__).resolve().parent / 'worlds'
_SUFFIXES = ('.yaml', '.yml', '.json')
#: Gazebo classic's world files, read by zros.sim.sdf.
SDF_SUFFIXES = ('.world', '.sdf')


class WorldFileError(ZrosError, ValueError):
    """A world file that cannot be used; the message starts with `file:line: key:`."""


def world_names() -> list[str]:
    """The worlds shipped with zros, by name."""
    return sorted(p.stem for p in WORLDS_DIR.glob('*.yaml'))


def world_path(world: str | os.PathLike) -> Path:
    """The file of `world`: a path as given, or a shipped world's name (`turtlebot3_world`)."""
    text = os.fspath(world)
    path = Path(text).expanduser()
    if path.suffix in _SUFFIXES + SDF_SUFFIXES or os.sep in text or path.exists():
        if not path.is_file():
            raise WorldFileError(f'{text}: no such world file')
        return path
    shipped = WORLDS_DIR / f'{text}.yaml'
    if not shipped.is_file():
        raise WorldFileError(f"unknown world '{text}' (shipped worlds: {', '.join(world_names())}; "
                             'or give the path of a .world/.sdf/.yaml/.json world file)')
    return shipped


def load_world(world: str | os.PathLike, *, on_warning: Callable[[str], None] | None = None) -> World:
    """Read a world file (a path, or the name of a shipped world); WorldFileError if it is bad.
    A Gazebo world (`.world`, `.sdf`) is cut at the lidar's height (zros.sim.sdf); what it
    leaves out is told to `on_warning`, one line each."""
    path = world_path(world)
    if path.suffix in SDF_SUFFIXES:
        from zros.sim.sdf import load_sdf_world
        return load_sdf_world(path, on_warning=on_warning)
    try:
        text = path.read_text(encoding='utf-8')
    except (OSError, UnicodeDecodeError) as exc:
        raise WorldFileError(f'{path}: cannot read: {exc}') from None
    return parse_world(text, source=path)


def parse_world(text: str, *, source: Path | str = '<string>') -> World:
    """A world from the text of a world file; `source` names it in error messages."""
    reader = _Reader(str(source))
    root = reader.compose(text)
    fields = reader.mapping(root, '', required={'obstacles'}, optional={'name', 'spawn', 'description'})
    name = reader.string(fields['name'], 'name') if 'name' in fields else Path(str(source)).stem
    spawn = Pose2D()
    if 'spawn' in fields:
        s = reader.mapping(fields['spawn'], 'spawn', required={'x', 'y'}, optional={'yaw'})
        spawn = Pose2D(reader.number(s['x'], 'spawn.x'), reader.number(s['y'], 'spawn.y'),
                       reader.number(s['yaw'], 'spawn.yaw') if 'yaw' in s else 0.0)
    obstacles = fields['obstacles']
    if isinstance(obstacles, yaml.ScalarNode) and obstacles.tag.endswith(':null'):
        items: list[yaml.Node] = []
    else:
        items = reader.sequence(obstacles, 'obstacles')
    polygons: list[tuple[np.ndarray, ...]] = []
    circles: list[tuple[float, float, float]] = []
    segments: list[tuple[float, float, float, float]] = []
    for index, item in enumerate(items):
        key = f'obstacles[{index}]'
        kinds = reader.mapping(item, key, optional=set(_SHAPES))
        if len(kinds) != 1:
            raise reader.error(item, key, f'must have exactly one shape key ({", ".join(_SHAPES)}), '
                                          f'got {", ".join(kinds) or "none"}')
        (kind, node), = kinds.items()
        shape = _SHAPES[kind](reader, node, f'{key}.{kind}')
        if kind == 'circle':
            circles.append(shape)
        elif kind == 'segment':
            segments.append(shape)
        else:
            polygons.append(shape)
    source_path = Path(source) if not str(source).startswith('<') else None
    return World(name=name, spawn=spawn, polygons=tuple(polygons), circles=np.array(circles).reshape(-1, 3),
                 segments=np.array(segments).reshape(-1, 4), source=source_path)


# -- shapes -----------------------------------------------------------------------------------
def _circle(reader: '_Reader', node: yaml.Node, key: str) -> tuple[float, float, float]:
    f = reader.mapping(node, key, required={'center', 'radius'})
    cx, cy = reader.point(f['center'], f'{key}.center')
    return (cx, cy, reader.positive(f['radius'], f'{key}.radius'))


def _box(reader: '_Reader', node: yaml.Node, key: str) -> tuple[np.ndarray, ...]:
    f = reader.mapping(node, key, required={'center', 'size'}, optional={'yaw'})
    cx, cy = reader.point(f['center'], f'{key}.center')
    sx, sy = reader.point(f['size'], f'{key}.size')
    for value, which in ((sx, 0), (sy, 1)):
        if not value > 0:
            raise reader.error(f['size'], f'{key}.size', f'size[{which}] must be > 0 (got {value:g})')
    yaw = reader.number(f['yaw'], f'{key}.yaw') if 'yaw' in f else 0.0
    return (box_loop(cx, cy, sx, sy, yaw),)


def _polygon(reader: '_Reader', node: yaml.Node, key: str) -> tuple[np.ndarray, ...]:
    f = reader.mapping(node, key, required={'points'})
    points = reader.sequence(f['points'], f'{key}.points')
    if len(points) < 3:
        raise reader.error(f['points'], f'{key}.points', f'a polygon needs at least 3 points (got {len(points)})')
    loop = np.array([reader.point(p, f'{key}.points[{i}]') for i, p in enumerate(points)])
    area = 0.5 * float(np.sum(loop[:, 0] * np.roll(loop[:, 1], -1) - np.roll(loop[:, 0], -1) * loop[:, 1]))
    if abs(area) < 1e-12:
        raise reader.error(f['points'], f'{key}.points', 'the points enclose no area')
    return (loop,)


def _regular_polygon(reader: '_Reader', node: yaml.Node, key: str) -> tuple[np.ndarray, ...]:
    f = reader.mapping(node, key, required={'center', 'sides', 'circumradius'}, optional={'rotation'})
    cx, cy = reader.point(f['center'], f'{key}.center')
    sides = reader.sides(f['sides'], f'{key}.sides')
    radius = reader.positive(f['circumradius'], f'{key}.circumradius')
    rotation = reader.number(f['rotation'], f'{key}.rotation') if 'rotation' in f else 0.0
    return (regular_polygon_loop(cx, cy, sides, radius, rotation),)


def _ring(reader: '_Reader', node: yaml.Node, key: str) -> tuple[np.ndarray, ...]:
    f = reader.mapping(node, key, required={'center', 'sides', 'inner_circumradius', 'outer_circumradius'},
                       optional={'rotation'})
    cx, cy = reader.point(f['center'], f'{key}.center')
    sides = reader.sides(f['sides'], f'{key}.sides')
    inner = reader.positive(f['inner_circumradius'], f'{key}.inner_circumradius')
    outer = reader.positive(f['outer_circumradius'], f'{key}.outer_circumradius')
    if not outer > inner:
        raise reader.error(f['outer_circumradius'], f'{key}.outer_circumradius',
                           f'must be > inner_circumradius ({outer:g} <= {inner:g})')
    rotation = reader.number(f['rotation'], f'{key}.rotation') if 'rotation' in f else 0.0
    return (regular_polygon_loop(cx, cy, sides, outer, rotation),
            regular_polygon_loop(cx, cy, sides, inner, rotation))


def _segment(reader: '_Reader', node: yaml.Node, key: str) -> tuple[float, float, float, float]:
    f = reader.mapping(node, key, required={'from', 'to'})
    a = reader.point(f['from'], f'{key}.from')
    b = reader.point(f['to'], f'{key}.to')
    if a == b:
        raise reader.error(f['to'], f'{key}.to', 'a segment needs two different points')
    return (*a, *b)


_SHAPES: dict[str, Callable[['_Reader', yaml.Node, str], Any]] = {
    'circle': _circle, 'box': _box, 'polygon': _polygon, 'regular_polygon': _regular_polygon,
    'ring': _ring, 'segment': _segment,
}


# -- typed reading with line numbers ----------------------------------------------------------
class _Reader:
    """Reads YAML nodes (which know their line) into typed values, or fails naming the key."""

    def __init__(self, source: str) -> None:
        self.source = source
        self._loader: yaml.SafeLoader | None = None

    def error(self, node: yaml.Node | None, key: str, message: str) -> WorldFileError:
        line = f':{node.start_mark.line + 1}' if node is not None else ''
        where = f' {key}:' if key else ''
        return WorldFileError(f'{self.source}{line}:{where} {message}')

    def compose(self, text: str) -> yaml.Node:
        self._loader = yaml.SafeLoader(text)
        try:
            node = self._loader.get_single_node()
        except yaml.MarkedYAMLError as exc:
            mark = exc.problem_mark or exc.context_mark
            line = f':{mark.line + 1}' if mark is not None else ''
            raise WorldFileError(f'{self.source}{line}: invalid YAML: {exc.problem or exc.context}') from None
        except yaml.YAMLError as exc:
            raise WorldFileError(f'{self.source}: invalid YAML: {exc}') from None
        if node is None:
            raise WorldFileError(f'{self.source}: empty world file (it needs at least `obstacles:`)')
        return node

    def _value(self, node: yaml.Node) -> Any:
        assert self._loader is not None
        return self._loader.construct_object(node, deep=True)

    def mapping(self, node: yaml.Node, key: str, *, required: set[str] = frozenset(),
                optional: set[str] = frozenset()) -> dict[str, yaml.Node]:
        if not isinstance(node, yaml.MappingNode):
            raise self.error(node, key, 'expected a mapping of keys to values')
        fields: dict[str, yaml.Node] = {}
        allowed = set(required) | set(optional)
        for key_node, value_node in node.value:
            name = str(self._value(key_node))
            if name not in allowed:
                where = f'{key}.{name}' if key else name
                raise self.error(key_node, where, f"unknown key (expected {', '.join(sorted(allowed))})")
            if name in fields:
                raise self.error(key_node, f'{key}.{name}' if key else name, 'given twice')
            fields[name] = value_node
        missing = sorted(set(required) - set(fields))
        if missing:
            raise self.error(node, key, f"missing {', '.join(repr(m) for m in missing)}")
        return fields

    def sequence(self, node: yaml.Node, key: str) -> list[yaml.Node]:
        if not isinstance(node, yaml.SequenceNode):
            raise self.error(node, key, 'expected a list')
        return list(node.value)

    def string(self, node: yaml.Node, key: str) -> str:
        if not isinstance(node, yaml.ScalarNode):
            raise self.error(node, key, 'expected a string')
        return str(self._value(node))

    def number(self, node: yaml.Node, key: str) -> float:
        value = self._value(node) if isinstance(node, yaml.ScalarNode) else None
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            shown = node.value if isinstance(node, yaml.ScalarNode) else 'a ' + type(node).__name__[:-4].lower()
            raise self.error(node, key, f'expected a number, got {shown!r}')
        if not math.isfinite(value):
            raise self.error(node, key, f'must be finite (got {value})')
        return float(value)

    def positive(self, node: yaml.Node, key: str) -> float:
        value = self.number(node, key)
        if not value > 0:
            raise self.error(node, key, f'must be > 0 (got {value:g})')
        return value

    def sides(self, node: yaml.Node, key: str) -> int:
        value = self.number(node, key)
        if value != int(value) or value < 3:
            raise self.error(node, key, f'must be a whole number >= 3 (got {value:g})')
        return int(value)

    def point(self, node: yaml.Node, key: str) -> tuple[float, float]:
        items = self.sequence(node, key)
        if len(items) != 2:
            raise self.error(node, key, f'expected [x, y], got {len(items)} values')
        return (self.number(items[0], f'{key}[0]'), self.number(items[1], f'{key}[1]'))
