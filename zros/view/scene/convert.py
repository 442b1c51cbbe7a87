"""Messages to scene data: numpy arrays ready for viser, computed without a browser.

Each function takes a message (or its numeric fields) and returns arrays in the message's own
frame; placing them in the fixed frame is the display's job (zros.view.scene.frames). Colours
follow RViz's defaults so that a student's screenshots look like the course's:

- occupancy grids: the "map" scheme (0 free -> white, 100 -> black, -1 unknown -> grey-green),
  the "costmap" scheme (free transparent, cost blue -> red, 99 inscribed cyan, 100 lethal
  magenta) and "raw" (the value as grey);
- laser scans: one point per finite beam inside [range_min, range_max];
- poses: arrows along each pose's +x axis; pose covariance: the 1-sigma ellipse of x, y;
- markers (visualization_msgs/Marker): one `MarkerShape` per marker.
"""
from __future__ import annotations

import math
from typing import Any, NamedTuple

import numpy as np

from zros.view.scene.geometry import Transform, pose_transform, quat_from_yaw, quat_rotate

__all__ = ['MAP_SCHEMES', 'occupancy_palette', 'occupancy_rgba', 'grid_placement', 'scan_points',
           'pointcloud2_points', 'poses_array', 'pose_arrows', 'covariance_ellipse', 'path_points',
           'MarkerShape', 'marker_shape', 'arrow_marker_points', 'MARKER_TYPES', 'rgb255', 'UNKNOWN_RGB',
           'yaw_pose', 'flat_arrow_mesh', 'polyline_segments', 'known_window']

MAP_SCHEMES = ('map', 'costmap', 'raw')
UNKNOWN_RGB = (112, 137, 134)


def occupancy_palette(scheme: str) -> np.ndarray:
    """(256, 4) uint8 RGBA for every cell value taken as uint8 (-1 is 255).

    Raises:
        ValueError: unknown scheme.
    """
    values = np.arange(256)
    palette = np.zeros((256, 4), dtype=np.uint8)
    palette[:, 3] = 255
    if scheme == 'map':
        occupancy = values[:101]
        palette[:101, :3] = (255 - occupancy * 255 // 100)[:, None]
        palette[101:128, :3] = (0, 255, 0)                  # out-of-range values stand out
        palette[128:255, 0] = 255
        palette[128:255, 1] = (values[128:255] - 128) * 255 // 126
        palette[255, :3] = UNKNOWN_RGB
    elif scheme == 'costmap':
        cost = values[1:99]
        palette[0] = (0, 0, 0, 0)                           # free space: see the map through it
        palette[1:99, 0] = cost * 255 // 100
        palette[1:99, 2] = 255 - cost * 255 // 100
        palette[99] = (0, 255, 255, 255)                    # inscribed
        palette[100] = (255, 0, 255, 255)                   # lethal
        palette[101:255, :3] = (0, 255, 0)
        palette[255] = (*UNKNOWN_RGB, 0)
    elif scheme == 'raw':
        palette[:, :3] = values[:, None]
    else:
        raise ValueError(f"unknown colour scheme '{scheme}' (one of {', '.join(MAP_SCHEMES)})")
    return palette


_PALETTES = {scheme: occupancy_palette(scheme) for scheme in MAP_SCHEMES}


def occupancy_rgba(data: Any, width: int, height: int, scheme: str = 'map', alpha: float = 1.0) -> np.ndarray:
    """The grid as an (height, width, 4) RGBA image, row i = grid row i (viser draws image rows towards +y).

    Raises:
        ValueError: the data does not have width x height cells, or the scheme is unknown.
    """
    cells = np.asarray(data).astype(np.int16, copy=False)
    if cells.size != width * height:
        raise ValueError(f'map data has {cells.size} cells, expected {width} x {height} = {width * height}')
    palette = _PALETTES.get(scheme)
    if palette is None:
        raise ValueError(f"unknown colour scheme '{scheme}' (one of {', '.join(MAP_SCHEMES)})")
    image = palette[(cells & 0xFF).reshape(height, width)]
    if alpha < 1.0:
        image[..., 3] = (image[..., 3] * max(0.0, alpha)).astype(np.uint8)
    return image


def grid_placement(info: Any, window: tuple[int, int, int, int] | None = None) -> tuple[Transform, float, float]:
    """Where an OccupancyGrid's image goes in the grid's frame: (centre pose, width [m], height [m]).

    The origin pose is the corner of cell (0, 0); the image plane is centred, so the centre is
    the origin moved by half the extent along the origin's own axes. `window` (row0, row1, col0,
    col1, ends exclusive) places a cropped part of the grid instead of all of it.
    """
    row0, row1, col0, col1 = window or (0, int(info.height), 0, int(info.width))
    origin = pose_transform(info.origin)
    res = info.resolution
    width_m, height_m = (col1 - col0) * res, (row1 - row0) * res
    centre = origin.apply(np.array([[(col0 + col1) / 2.0 * res, (row0 + row1) / 2.0 * res, 0.0]]))[0]
    return Transform(centre, origin.rotation), width_m, height_m


def known_window(cells: np.ndarray, margin: int) -> tuple[int, int, int, int] | None:
    """(row0, row1, col0, col1) of the known cells (not -1) of a 2D grid, widened by `margin`
    cells and clipped to the grid; None if every cell is unknown."""
    known = cells != -1
    rows, cols = np.flatnonzero(known.any(axis=1)), np.flatnonzero(known.any(axis=0))
    if rows.size == 0:
        return None
    height, width = cells.shape
    return (max(0, int(rows[0]) - margin), min(height, int(rows[-1]) + 1 + margin),
            max(0, int(cols[0]) - margin), min(width, int(cols[-1]) + 1 + margin))


def scan_points(ranges: Any, angle_min: float, angle_increment: float, range_min: float,
                range_max: float) -> np.ndarray:
    """(N, 3) float32 points [m] of the valid beams of a LaserScan, in the scan's frame."""
    r = np.asarray(ranges, dtype=np.float32)
    angles = angle_min + angle_increment * np.arange(r.size, dtype=np.float32)
    valid = np.isfinite(r) & (r >= range_min) & (r <= range_max)
    r, angles = r[valid], angles[valid]
    return np.stack([r * np.cos(angles), r * np.sin(angles), np.zeros_like(r)], axis=1)


_POINTFIELD_DTYPES = {1: 'i1', 2: 'u1', 3: 'i2', 4: 'u2', 5: 'i4', 6: 'u4', 7: 'f4', 8: 'f8'}


def pointcloud2_points(msg: Any) -> tuple[np.ndarray, np.ndarray | None]:
    """(N, 3) float32 finite xyz of a PointCloud2 and, when it has an `rgb`/`rgba` field, (N, 3)
    uint8 colours; otherwise None.

    Raises:
        ValueError: no x/y/z fields, or data shorter than the declared points.
    """
    fields = {f.name: f for f in msg.fields}
    if not {'x', 'y', 'z'} <= fields.keys():
        raise ValueError(f"PointCloud2 has no x, y, z fields (it has {', '.join(fields) or 'none'})")
    order = '>' if msg.is_bigendian else '<'
    names, formats, offsets = [], [], []
    for name in ('x', 'y', 'z', 'rgb', 'rgba'):
        field = fields.get(name)
        if field is None:
            continue
        if name in ('rgb', 'rgba'):
            names.append('rgb')
            formats.append(order + 'u4')
        else:
            names.append(name)
            formats.append(order + _POINTFIELD_DTYPES.get(field.datatype, 'f4'))
        offsets.append(field.offset)
        if name == 'rgb':
            break
    count = int(msg.width) * int(msg.height)
    dtype = np.dtype({'names': names, 'formats': formats, 'offsets': offsets, 'itemsize': int(msg.point_step)})
    raw = np.asarray(msg.data, dtype=np.uint8).reshape(-1)
    if count == 0:
        return np.zeros((0, 3), dtype=np.float32), None
    if msg.height > 1 and msg.row_step:
        rows = raw[:int(msg.row_step) * int(msg.height)].reshape(int(msg.height), int(msg.row_step))
        raw = np.ascontiguousarray(rows[:, :int(msg.width) * int(msg.point_step)]).reshape(-1)
    if raw.size < count * int(msg.point_step):
        raise ValueError(f'PointCloud2 data has {raw.size} bytes, {count} points of {msg.point_step} need more')
    records = raw[:count * int(msg.point_step)].view(dtype)
    xyz = np.stack([records['x'], records['y'], records['z']], axis=1).astype(np.float32)
    finite = np.isfinite(xyz).all(axis=1)
    colors = None
    if 'rgb' in names:
        packed = records['rgb'][finite]
        colors = np.stack([(packed >> 16) & 0xFF, (packed >> 8) & 0xFF, packed & 0xFF], axis=1).astype(np.uint8)
    return xyz[finite], colors


def poses_array(poses: Any) -> tuple[np.ndarray, np.ndarray]:
    """Positions (N, 3) and xyzw orientations (N, 4) of a sequence of geometry_msgs/Pose."""
    flat = [(p.position.x, p.position.y, p.position.z, p.orientation.x, p.orientation.y,
             p.orientation.z, p.orientation.w) for p in poses]
    values = np.asarray(flat, dtype=np.float64).reshape(-1, 7)
    return values[:, :3], values[:, 3:]


def pose_arrows(positions: np.ndarray, orientations: np.ndarray, length: float) -> np.ndarray:
    """(N, 2, 3) start/end points of arrows of `length` [m] along each pose's +x axis."""
    norms = np.linalg.norm(orientations, axis=1, keepdims=True)
    unit = np.where(norms > 1e-12, orientations / np.maximum(norms, 1e-12), [0.0, 0.0, 0.0, 1.0])
    tips = positions + quat_rotate(unit, np.tile([length, 0.0, 0.0], (len(positions), 1)))
    return np.stack([positions, tips], axis=1).astype(np.float32)


def covariance_ellipse(covariance: Any, *, sigma: float = 1.0, segments: int = 48) -> np.ndarray:
    """(segments, 3) points of the `sigma` ellipse of the x-y block of a 6x6 pose covariance,
    centred on the origin, in the pose's parent frame."""
    cov = np.asarray(covariance, dtype=np.float64).reshape(6, 6)[:2, :2]
    cov = (cov + cov.T) / 2.0
    eigenvalues, eigenvectors = np.linalg.eigh(cov)
    radii = sigma * np.sqrt(np.clip(eigenvalues, 0.0, None))
    angles = np.linspace(0.0, 2.0 * math.pi, segments, endpoint=False)
    circle = np.stack([np.cos(angles) * radii[0], np.sin(angles) * radii[1]], axis=1)
    xy = circle @ eigenvectors.T
    return np.column_stack([xy, np.zeros(segments)])


def path_points(poses: Any) -> np.ndarray:
    """(N, 3) positions of a nav_msgs/Path's PoseStamped list."""
    return np.asarray([(p.pose.position.x, p.pose.position.y, p.pose.position.z) for p in poses],
                      dtype=np.float64).reshape(-1, 3)


def rgb255(color: Any) -> tuple[int, int, int]:
    """A std_msgs/ColorRGBA (0..1 floats) as 0..255 integers."""
    return (int(round(min(max(color.r, 0.0), 1.0) * 255)), int(round(min(max(color.g, 0.0), 1.0) * 255)),
            int(round(min(max(color.b, 0.0), 1.0) * 255)))


MARKER_TYPES = {0: 'arrow', 1: 'cube', 2: 'sphere', 3: 'cylinder', 4: 'line_strip', 5: 'line_list',
                6: 'cube_list', 7: 'sphere_list', 8: 'points', 9: 'text', 10: 'mesh', 11: 'triangle_list',
                12: 'arrow_strip'}


class MarkerShape(NamedTuple):
    """One marker, ready to draw: `kind` (a MARKER_TYPES value), its pose in the header's frame,
    scale [m], RGB and alpha, and for list types the points (N, 3) and per-point RGB (N, 3)."""
    kind: str
    pose: Transform
    scale: tuple[float, float, float]
    rgb: tuple[int, int, int]
    alpha: float
    points: np.ndarray
    colors: np.ndarray | None
    text: str


def marker_shape(marker: Any) -> MarkerShape:
    """The drawable content of one visualization_msgs/Marker (action ADD/MODIFY).

    Raises:
        ValueError: unknown marker type.
    """
    kind = MARKER_TYPES.get(int(marker.type))
    if kind is None:
        raise ValueError(f'unknown marker type {marker.type}')
    points = np.asarray([(p.x, p.y, p.z) for p in marker.points], dtype=np.float64).reshape(-1, 3)
    colors = None
    if len(marker.colors) and len(marker.colors) == len(points):
        colors = np.asarray([rgb255(c) for c in marker.colors], dtype=np.uint8)
    scale = (float(marker.scale.x), float(marker.scale.y), float(marker.scale.z))
    return MarkerShape(kind, pose_transform(marker.pose), scale, rgb255(marker.color), float(marker.color.a),
                       points, colors, str(marker.text))


def arrow_marker_points(shape: MarkerShape) -> np.ndarray:
    """(1, 2, 3) start/end of an ARROW marker in the marker's frame: two points if given, else
    the pose's +x axis scaled by scale.x."""
    if len(shape.points) >= 2:
        return shape.points[:2][None].astype(np.float32)
    start = shape.pose.translation
    tip = start + quat_rotate(shape.pose.rotation, np.array([[shape.scale[0], 0.0, 0.0]]))[0]
    return np.stack([start, tip])[None].astype(np.float32)


def yaw_pose(x: float, y: float, yaw: float) -> Transform:
    """A planar pose as a Transform (used by the tools and tests)."""
    return Transform(np.array([x, y, 0.0]), quat_from_yaw(yaw))



def polyline_segments(points: np.ndarray, *, closed: bool = False) -> np.ndarray:
    """(M, 2, 3) segments joining consecutive (N, 3) points (and the last to the first if closed)."""
    points = np.asarray(points, dtype=np.float32).reshape(-1, 3)
    if len(points) < 2:
        return np.zeros((0, 2, 3), dtype=np.float32)
    ends = np.roll(points, -1, axis=0) if closed else points[1:]
    starts = points if closed else points[:-1]
    return np.stack([starts, ends], axis=1)


def flat_arrow_mesh(length: float) -> tuple[np.ndarray, np.ndarray]:
    """Vertices (7, 3) and faces (3, 3) of a flat arrow along +x in the z = 0 plane, `length` [m]
    long: one instanced mesh draws thousands of poses (particles) in one call."""
    w, head = 0.05 * length, 0.35 * length
    vertices = np.array([[0.0, -w, 0.0], [length - head, -w, 0.0], [length - head, w, 0.0], [0.0, w, 0.0],
                         [length - head, -2.5 * w, 0.0], [length, 0.0, 0.0], [length - head, 2.5 * w, 0.0]],
                        dtype=np.float32)
    faces = np.array([[0, 1, 2], [0, 2, 3], [4, 5, 6]], dtype=np.uint32)
    return vertices, faces
