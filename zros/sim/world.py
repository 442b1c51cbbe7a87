"""A 2D world: the obstacles a robot's lidar sees and its body bumps into, as plain numpy data.

Gazebo's worlds are 3D; the TurtleBot3 only ever meets them in one plane (the lidar's, 0.182 m
above the floor), so a zros world is the cut through that plane: circles, closed polygons
(boxes, regular polygons, rings, free polygons) and zero-thickness segments, in metres, in
Gazebo's world frame (which is also the `map` frame of ROBOTIS's reference maps).

Everything that asks the world a question works on these arrays, vectorised:
- `edges` (N, 4) `x1, y1, x2, y2`: every polygon side and every segment, for ray casting and
  for the physics' static bodies;
- `circles` (M, 3) `cx, cy, r`;
- `polygons`: each area shape as a tuple of closed loops (K, 2), filled by the even-odd rule
  (a ring is its outer and inner loop), for inside tests and the ground-truth raster.

A world may also hold pushable `bodies` (a Gazebo world's non-static models): they start where
the file puts them and move in the simulation (zros.sim.simulation), so `edges`, `circles` and
every query here are the fixed obstacles only.

Worlds come from files (`zros.sim.world_file.load_world`); this module only builds and queries.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

__all__ = ['World', 'Body', 'Pose2D', 'box_loop', 'regular_polygon_loop', 'loop_edges']


@dataclass(frozen=True)
class Pose2D:
    """A planar pose: x, y [m] and yaw [rad, counter-clockwise from +x]."""
    x: float = 0.0
    y: float = 0.0
    yaw: float = 0.0


def box_loop(cx: float, cy: float, sx: float, sy: float, yaw: float = 0.0) -> np.ndarray:
    """The corners (4, 2) of an sx-by-sy rectangle centred on (cx, cy), its sx side along `yaw`."""
    c, s = math.cos(yaw), math.sin(yaw)
    half = np.array([[-sx, -sy], [sx, -sy], [sx, sy], [-sx, sy]]) / 2.0
    rotation = np.array([[c, -s], [s, c]])
    return half @ rotation.T + (cx, cy)


def regular_polygon_loop(cx: float, cy: float, sides: int, circumradius: float,
                         rotation: float = 0.0) -> np.ndarray:
    """The corners (sides, 2) of a regular polygon; the first corner is at angle `rotation` [rad]
    from +x (0: a corner on the +x axis, as the TurtleBot3 world's hexagons)."""
    angles = rotation + 2.0 * math.pi * np.arange(sides) / sides
    return np.column_stack([cx + circumradius * np.cos(angles), cy + circumradius * np.sin(angles)])


def loop_edges(loop: np.ndarray) -> np.ndarray:
    """The sides (K, 4) `x1, y1, x2, y2` of a closed loop of K corners."""
    return np.hstack([loop, np.roll(loop, -1, axis=0)])


@dataclass(frozen=True, eq=False)
class Body:
    """A pushable obstacle (a non-static model): its section at the start, in the world frame.

    Attributes:
        name: the model's name.
        polygons: convex loops (K, 2) [m] (a box's section; other loops are taken as their hull).
        circles: (M, 3) `cx, cy, r` [m].
        mass: [kg], the sum of its links' `<inertial><mass>` (SDF's default 1 kg a link).
    """
    name: str
    polygons: tuple[np.ndarray, ...] = ()
    circles: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    mass: float = 1.0


@dataclass(frozen=True, eq=False)
class World:
    """A world's obstacles and where a robot starts. Immutable: build a new one to change it.

    Attributes:
        name: the world's name (`turtlebot3_world`).
        spawn: where a robot starts when nothing else is said (the launch files' defaults).
        polygons: area obstacles, each a tuple of closed loops (K, 2) filled even-odd.
        circles: (M, 3) `cx, cy, r` [m].
        segments: (L, 4) zero-thickness walls `x1, y1, x2, y2` [m].
        source: the file it was loaded from, if any.
        bodies: pushable obstacles, not part of `edges` or `circles`.
    """
    name: str
    spawn: Pose2D = Pose2D()
    polygons: tuple[tuple[np.ndarray, ...], ...] = ()
    circles: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    segments: np.ndarray = field(default_factory=lambda: np.zeros((0, 4)))
    source: Path | None = None
    bodies: tuple[Body, ...] = ()

    def __post_init__(self) -> None:
        circles = np.asarray(self.circles, dtype=np.float64).reshape(-1, 3)
        segments = np.asarray(self.segments, dtype=np.float64).reshape(-1, 4)
        polygons = tuple(tuple(np.asarray(loop, dtype=np.float64).reshape(-1, 2) for loop in shape)
                         for shape in self.polygons)
        object.__setattr__(self, 'circles', circles)
        object.__setattr__(self, 'segments', segments)
        object.__setattr__(self, 'polygons', polygons)
        edges = [loop_edges(loop) for shape in polygons for loop in shape] + [segments]
        object.__setattr__(self, 'edges', np.vstack(edges) if edges else np.zeros((0, 4)))
        for array in (circles, segments, self.edges, *(loop for shape in polygons for loop in shape)):
            array.flags.writeable = False

    # `edges` is derived in __post_init__; declared here for type checkers and readers.
    edges: np.ndarray = field(init=False, repr=False)

    @property
    def is_empty(self) -> bool:
        return len(self.edges) == 0 and len(self.circles) == 0

    def bounds(self) -> tuple[float, float, float, float] | None:
        """`(xmin, ymin, xmax, ymax)` of all obstacles [m], or None for an empty world."""
        if self.is_empty:
            return None
        xs = [self.edges[:, 0], self.edges[:, 2], self.circles[:, 0] - self.circles[:, 2],
              self.circles[:, 0] + self.circles[:, 2]]
        ys = [self.edges[:, 1], self.edges[:, 3], self.circles[:, 1] - self.circles[:, 2],
              self.circles[:, 1] + self.circles[:, 2]]
        x, y = np.concatenate(xs), np.concatenate(ys)
        return (float(x.min()), float(y.min()), float(x.max()), float(y.max()))

    def contains(self, points: np.ndarray) -> np.ndarray:
        """Whether each point (N, 2) lies inside an obstacle (a polygon or a circle): (N,) bool."""
        points = np.asarray(points, dtype=np.float64).reshape(-1, 2)
        inside = np.zeros(len(points), dtype=bool)
        for shape in self.polygons:
            inside |= _even_odd(points, np.vstack([loop_edges(loop) for loop in shape]))
        if len(self.circles):
            d2 = ((points[:, None, :] - self.circles[None, :, :2]) ** 2).sum(axis=2)
            inside |= (d2 < self.circles[None, :, 2] ** 2).any(axis=1)
        return inside

    def distance(self, points: np.ndarray) -> np.ndarray:
        """Distance [m] from each point (N, 2) to the nearest obstacle surface: (N,); inf in an
        empty world. Zero-or-positive everywhere, inside obstacles too (see `contains`)."""
        points = np.asarray(points, dtype=np.float64).reshape(-1, 2)
        best = np.full(len(points), np.inf)
        if len(self.edges):
            a, b = self.edges[None, :, :2], self.edges[None, :, 2:]
            ab = b - a
            length2 = np.maximum((ab ** 2).sum(axis=2), 1e-300)
            t = np.clip(((points[:, None, :] - a) * ab).sum(axis=2) / length2, 0.0, 1.0)
            nearest = a + t[..., None] * ab
            best = np.minimum(best, np.sqrt(((points[:, None, :] - nearest) ** 2).sum(axis=2)).min(axis=1))
        if len(self.circles):
            centre = np.sqrt(((points[:, None, :] - self.circles[None, :, :2]) ** 2).sum(axis=2))
            best = np.minimum(best, np.abs(centre - self.circles[None, :, 2]).min(axis=1))
        return best

    def collides(self, x: float, y: float, radius: float) -> bool:
        """Whether a disc of `radius` at (x, y) overlaps an obstacle (a robot's body, say)."""
        point = np.array([[x, y]])
        return bool(self.contains(point)[0] or self.distance(point)[0] < radius)


def _even_odd(points: np.ndarray, edges: np.ndarray) -> np.ndarray:
    """Even-odd inside test of points (N, 2) against the closed loops whose sides are `edges`."""
    px, py = points[:, 0:1], points[:, 1:2]
    x1, y1, x2, y2 = (edges[None, :, k] for k in range(4))
    straddles = (y1 > py) != (y2 > py)
    with np.errstate(divide='ignore', invalid='ignore'):
        x_cross = x1 + (py - y1) * (x2 - x1) / (y2 - y1)
    return ((straddles & (px < x_cross)).sum(axis=1) % 2) == 1
