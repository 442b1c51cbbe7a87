"""Map files as nav2_map_server reads and writes them: a YAML file plus a PGM or PNG image.

A saved map is two files, `NAME.yaml` and `NAME.pgm` (or `.png`), whose rules come from
nav2_map_server's map_io (Humble), so a map made by ROS loads in zros and one made by zros
loads in ROS:

- YAML keys: `image` (path, relative to the YAML file's folder), `resolution` [m/cell],
  `origin` [x, y, yaw] of the lower-left pixel, `negate` (0/1 or a bool), `occupied_thresh`,
  `free_thresh`, and `mode` (`trinary` when absent, `scale` or `raw`).
- Loading: each pixel's shade is the mean of its colour channels over their maximum (in
  trinary mode an alpha channel is averaged in too); occupancy is 1 - shade (shade if negated).
  Trinary: above occupied_thresh -> 100, below free_thresh -> 0, else -1. Scale: a transparent
  pixel -> -1, then the thresholds, and in between rint(100 (occ - free) / (occupied - free)).
  Raw: round(255 shade) if within 0..100, else -1. The image's top row is the grid's last row.
- Saving: trinary writes 254 (free: cell <= rint(100 free_thresh)), 0 (occupied: cell >=
  rint(100 occupied_thresh)) and 205 (unknown or in between); scale writes grey
  (100 - cell) / 100 with unknown transparent (PNG only); raw writes the cell value, unknown 255.

Two choices differ from nav2 on purpose, and are documented in docs/slam.md:
- The default free threshold written is 0.196 (ROS 1's and ROBOTIS's), not 0.25: with 0.25 the
  unknown shade 205 (occupancy 0.196) reads back as free (slam_toolbox#587, navigation2#5138),
  so a map saved and reloaded loses its unknown space. Pass `free_thresh=0.25` for nav2's files.
- Numbers are written in full (shortest exact form) instead of yaml-cpp's three significant
  digits, which would move an origin such as -12.35 by a cell. Round values read the same.

Everything here is numpy on whole images (no loop per pixel); images are read and written
with zros.image_io (Pillow).
"""
from __future__ import annotations

import math
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import yaml

from zros.errors import ZrosError
from zros.grid_geometry import GridGeometry
from zros.image_io import ImageError, decode_image, encode_png
from zros.rotations import quaternion_from_yaw, yaw_from_quaternion

__all__ = ['MapFileError', 'MapNotFoundError', 'MapMetadataError', 'MapImageError', 'MapYaml', 'OccupancyMap', 'MAP_MODES', 'IMAGE_FORMATS', 'DEFAULT_OCCUPIED_THRESH',
           'DEFAULT_FREE_THRESH', 'read_map_yaml', 'read_image', 'image_to_occupancy', 'load_map',
           'occupancy_to_image', 'save_map', 'map_to_msg', 'map_from_msg', 'resample']

MAP_MODES = ('trinary', 'scale', 'raw')
IMAGE_FORMATS = ('pgm', 'png')
DEFAULT_OCCUPIED_THRESH = 0.65
DEFAULT_FREE_THRESH = 0.196
FREE, OCCUPIED, UNKNOWN = 0, 100, -1
#: Trinary pixel values, as map_saver writes them.
PIXEL_FREE, PIXEL_OCCUPIED, PIXEL_UNKNOWN = 254, 0, 205


class MapFileError(ZrosError, ValueError):
    """A map file that cannot be read or written. The text is one line naming the file and,
    for a YAML problem, the key."""


class MapNotFoundError(MapFileError):
    """The YAML file does not exist or cannot be read (LoadMap's RESULT_MAP_DOES_NOT_EXIST)."""


class MapMetadataError(MapFileError):
    """The YAML file is not valid YAML or has a missing or bad key (RESULT_INVALID_MAP_METADATA)."""


class MapImageError(MapFileError):
    """The image is missing or unreadable (RESULT_INVALID_MAP_DATA)."""


@dataclass(frozen=True)
class MapYaml:
    """The contents of a map's YAML file (nav2's LoadParameters)."""
    image: Path
    resolution: float                       # [m/cell]
    origin: tuple[float, float, float]      # x [m], y [m], yaw [rad] of the lower-left pixel
    negate: bool
    occupied_thresh: float
    free_thresh: float
    mode: str = 'trinary'


@dataclass
class OccupancyMap:
    """An occupancy grid as numpy: `data[row, col]` is the cell at x = origin + col * resolution,
    y = origin + row * resolution (row 0 is the lowest y, as in nav_msgs/OccupancyGrid), with
    100 occupied, 0 free, -1 unknown (or graded 0..100). `geometry` places the cells in the
    world, the origin's yaw included."""
    data: np.ndarray                        # (height, width) int8
    resolution: float                       # [m/cell]
    origin: tuple[float, float, float]      # x [m], y [m], yaw [rad] of cell (0, 0)'s corner

    @property
    def geometry(self) -> GridGeometry:
        """Where the cells lie (made on each call: `data`, `resolution` and `origin` may be reassigned)."""
        return GridGeometry(self.resolution, self.origin, self.data.shape)

    @property
    def width(self) -> int:
        return int(self.data.shape[1])

    @property
    def height(self) -> int:
        return int(self.data.shape[0])


# -- reading ------------------------------------------------------------------------------------
#: Numbers in exponent form that YAML 1.1 (PyYAML) reads as strings for want of a dot or an
#: exponent sign (`1e-05`, `5E3`), and yaml-cpp (nav2) and YAML 1.2 as numbers.
_EXPONENT_FORM = re.compile(r'[-+]?([0-9]+\.?[0-9]*|\.[0-9]+)[eE][-+]?[0-9]+')

def read_map_yaml(path: str | Path) -> MapYaml:
    """Parse and check a map YAML file.

    Raises:
        MapFileError: unreadable file, bad YAML, or a missing or bad key (named in the text).
    """
    path = Path(path).expanduser()
    try:
        text = path.read_text()
    except OSError as exc:
        raise MapNotFoundError(f'{path}: cannot read the map file: {exc.strerror or exc}') from None
    try:
        doc = yaml.safe_load(text)
    except yaml.YAMLError as exc:
        mark = getattr(exc, 'problem_mark', None)
        where = f':{mark.line + 1}' if mark is not None else ''
        reason = getattr(exc, 'problem', None) or str(exc).splitlines()[0]
        raise MapMetadataError(f'{path}{where}: not valid YAML: {reason}') from None
    if not isinstance(doc, dict):
        raise MapMetadataError(f'{path}: a map file is a YAML mapping with image, resolution, origin, '
                           'occupied_thresh and free_thresh')

    def fail(key: str, why: str) -> MapFileError:
        return MapMetadataError(f'{path}: {key}: {why}')

    def required(key: str) -> Any:
        if key not in doc or doc[key] is None:
            raise fail(key, 'missing')
        return doc[key]

    def number(key: str, value: Any) -> float:
        if isinstance(value, str) and _EXPONENT_FORM.fullmatch(value.strip()):
            value = float(value)
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
            raise fail(key, f'must be a number, got {value!r}')
        return float(value)

    image = required('image')
    if not isinstance(image, str) or not image:
        raise fail('image', f'must be the image file name, got {image!r}')
    image_path = Path(image).expanduser()
    if not image_path.is_absolute():
        image_path = path.parent / image_path
    resolution = number('resolution', required('resolution'))
    if resolution <= 0:
        raise fail('resolution', f'must be > 0 [m/cell], got {resolution:g}')
    origin = required('origin')
    if not isinstance(origin, list) or len(origin) != 3:
        count = len(origin) if isinstance(origin, list) else 'not a list'
        raise fail('origin', f'must have 3 elements [x, y, yaw], not {count}')
    origin_values = tuple(number('origin', v) for v in origin)
    thresholds = {}
    for key in ('occupied_thresh', 'free_thresh'):
        thresholds[key] = number(key, required(key))
        if not 0.0 <= thresholds[key] <= 1.0:
            raise fail(key, f'must be within 0..1, got {thresholds[key]:g}')
    mode = doc.get('mode', 'trinary')
    if mode not in MAP_MODES:
        raise fail('mode', f'unsupported {mode!r} (trinary, scale or raw)')
    negate = doc.get('negate', 0)
    if isinstance(negate, bool) or negate in (0, 1):
        negate = bool(negate)
    else:
        raise fail('negate', f'must be 0, 1, true or false, got {negate!r}')
    return MapYaml(image_path, resolution, origin_values, negate,  # type: ignore[arg-type]
                   thresholds['occupied_thresh'], thresholds['free_thresh'], mode)


def read_image(path: str | Path) -> tuple[np.ndarray, bool]:
    """An image's samples as floats: ((H, W, C) array in 0..1, has_alpha), C in 1..4, row 0 at
    the top. Reads what zros.image_io reads: PGM/PPM (8 or 16 bit), PNG, and Pillow's other formats.

    Raises:
        MapFileError: the file is missing or not an image.
    """
    path = Path(path)
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise MapImageError(f'{path}: cannot read the map image: {exc.strerror or exc}') from None
    try:
        pixels = decode_image(data)
    except ImageError as exc:
        raise MapImageError(f'{path}: {exc}') from None
    return pixels.astype(np.float64) / np.iinfo(pixels.dtype).max, pixels.shape[2] in (2, 4)


def image_to_occupancy(samples: np.ndarray, has_alpha: bool, *, mode: str = 'trinary', negate: bool = False,
                       occupied_thresh: float = DEFAULT_OCCUPIED_THRESH,
                       free_thresh: float = DEFAULT_FREE_THRESH) -> np.ndarray:
    """nav2's per-pixel rule, on the whole image: (H, W, C) samples in 0..1 (row 0 at the top,
    as read_image gives) -> (H, W) int8 occupancy with row 0 the lowest y."""
    colour = samples[..., :3] if samples.shape[2] >= 3 else samples[..., :1]
    alpha = samples[..., -1] if has_alpha else np.ones(samples.shape[:2])
    shade = colour.mean(axis=2)
    if mode == 'trinary' and has_alpha:
        shade = (shade * 3.0 + alpha) / 4.0
    occ = shade if negate else 1.0 - shade
    if mode == 'raw':
        percent = np.round(shade * 255.0)
        cells = np.where((percent >= 0) & (percent <= 100), percent, UNKNOWN)
    else:
        cells = np.full(shade.shape, UNKNOWN, dtype=np.float64)
        if mode == 'scale':
            span = occupied_thresh - free_thresh
            graded = np.rint((occ - free_thresh) / span * 100.0) if span > 0 else np.full(shade.shape, UNKNOWN)
            cells = graded
        cells = np.where(occ > occupied_thresh, OCCUPIED, cells)
        cells = np.where(occ < free_thresh, FREE, cells)
        if mode == 'scale':
            cells = np.where(alpha < 1.0, UNKNOWN, cells)
    return np.ascontiguousarray(cells[::-1]).astype(np.int8)


def load_map(yaml_path: str | Path) -> OccupancyMap:
    """Load a map as nav2's map_server does (module docstring).

    Raises:
        MapFileError: one line naming the file and what is wrong.
    """
    meta = read_map_yaml(yaml_path)
    try:
        samples, has_alpha = read_image(meta.image)
    except MapFileError as exc:
        raise MapImageError(f'{Path(yaml_path).expanduser()}: image: {exc}') from None
    data = image_to_occupancy(samples, has_alpha, mode=meta.mode, negate=meta.negate,
                              occupied_thresh=meta.occupied_thresh, free_thresh=meta.free_thresh)
    return OccupancyMap(data, meta.resolution, meta.origin)


# -- writing ------------------------------------------------------------------------------------
def occupancy_to_image(data: np.ndarray, *, mode: str = 'trinary',
                       occupied_thresh: float = DEFAULT_OCCUPIED_THRESH,
                       free_thresh: float = DEFAULT_FREE_THRESH) -> np.ndarray:
    """map_saver's per-cell rule: (H, W) occupancy (row 0 lowest y) -> uint8 pixels, top row
    first: (H, W) grey for trinary and raw, (H, W, 4) RGBA for scale (unknown transparent)."""
    cells = np.asarray(data, dtype=np.int16)[::-1]
    unknown = (cells < 0) | (cells > 100)
    if mode == 'trinary':
        free_int, occupied_int = int(np.rint(free_thresh * 100.0)), int(np.rint(occupied_thresh * 100.0))
        pixels = np.full(cells.shape, PIXEL_UNKNOWN, dtype=np.uint8)
        pixels[cells >= occupied_int] = PIXEL_OCCUPIED
        pixels[cells <= free_int] = PIXEL_FREE
        pixels[unknown] = PIXEL_UNKNOWN
        return pixels
    if mode == 'raw':
        return np.where(unknown, 255, cells).astype(np.uint8)
    if mode == 'scale':
        grey = np.rint((100.0 - np.clip(cells, 0, 100)) / 100.0 * 255.0)
        grey = np.where(unknown, 128, grey).astype(np.uint8)
        alpha = np.where(unknown, 0, 255).astype(np.uint8)
        return np.stack([grey, grey, grey, alpha], axis=2)
    raise ValueError(f"unsupported map mode '{mode}' (trinary, scale or raw)")


def save_map(grid: OccupancyMap, name: str | Path, *, mode: str = 'trinary', image_format: str | None = None,
             occupied_thresh: float = DEFAULT_OCCUPIED_THRESH,
             free_thresh: float = DEFAULT_FREE_THRESH) -> tuple[Path, Path]:
    """Write `NAME.yaml` and `NAME.pgm`/`.png` as map_saver does (module docstring).

    Args:
        grid: the map.
        name: the path without extension (`~` is expanded).
        mode: trinary, scale or raw.
        image_format: pgm or png; default pgm, png for scale (which needs transparency).
        occupied_thresh, free_thresh: 0..1, free < occupied.

    Returns:
        (yaml path, image path).

    Raises:
        MapFileError: bad arguments, or the files cannot be written.
    """
    if mode not in MAP_MODES:
        raise MapFileError(f"mode: unsupported '{mode}' (trinary, scale or raw)")
    image_format = (image_format or ('png' if mode == 'scale' else 'pgm')).lower()
    if image_format not in IMAGE_FORMATS:
        raise MapFileError(f"image format: unsupported '{image_format}' (pgm or png)")
    if mode == 'scale' and image_format == 'pgm':
        raise MapFileError("mode 'scale' needs transparency, which pgm has not: use --fmt png")
    if not (0.0 <= free_thresh < occupied_thresh <= 1.0):
        raise MapFileError(f'thresholds: need 0 <= free ({free_thresh:g}) < occupied ({occupied_thresh:g}) <= 1')
    base = Path(name).expanduser()
    image_path = base.with_name(base.name + '.' + image_format)
    yaml_path = base.with_name(base.name + '.yaml')
    pixels = occupancy_to_image(grid.data, mode=mode, occupied_thresh=occupied_thresh, free_thresh=free_thresh)
    if image_format == 'pgm':
        header = (f'P5\n# CREATOR: map_saver.cpp {grid.resolution:.3f} m/pix\n'
                  f'{grid.width} {grid.height}\n255\n').encode()
        image_bytes = header + pixels.tobytes()
    else:
        image_bytes = encode_png(pixels)
    x, y, yaw = grid.origin
    lines = [f'image: {image_path.name}', f'mode: {mode}', f'resolution: {_number(grid.resolution, single=True)}',
             f'origin: [{_number(x)}, {_number(y)}, {_number(yaw)}]', 'negate: 0',
             f'occupied_thresh: {_number(occupied_thresh)}', f'free_thresh: {_number(free_thresh)}']
    try:
        image_path.write_bytes(image_bytes)
        yaml_path.write_text('\n'.join(lines))             # no final newline, as yaml-cpp's emitter
    except OSError as exc:
        raise MapFileError(f'{exc.filename or base}: cannot write the map: {exc.strerror or exc}') from None
    return yaml_path, image_path


def _number(value: float, *, single: bool = False) -> str:
    """The shortest text that reads back as `value` (as float32 when `single`), integers without
    '.0', as yaml-cpp prints round values."""
    value = float(value) + 0.0                             # -0.0 -> 0.0
    text = str(np.float32(value)) if single else repr(value)
    return text[:-2] if text.endswith('.0') else text


# -- messages -----------------------------------------------------------------------------------
def map_to_msg(grid: OccupancyMap, *, frame_id: str = 'map', stamp: Any = None) -> Any:
    """A nav_msgs/OccupancyGrid for the map (`stamp`: a builtin_interfaces/Time, also used as
    map_load_time)."""
    from interfaces.nav_msgs.msg import OccupancyGrid
    msg = OccupancyGrid()
    msg.header.frame_id = frame_id
    if stamp is not None:
        msg.header.stamp = stamp
        msg.info.map_load_time = stamp
    msg.info.resolution = float(grid.resolution)
    msg.info.width, msg.info.height = grid.width, grid.height
    x, y, yaw = grid.origin
    msg.info.origin.position.x, msg.info.origin.position.y = float(x), float(y)
    q = msg.info.origin.orientation
    q.x, q.y, q.z, q.w = quaternion_from_yaw(float(yaw))
    msg.data = np.ascontiguousarray(grid.data, dtype=np.int8).ravel()
    return msg


def map_from_msg(msg: Any) -> OccupancyMap:
    """The numpy view of a nav_msgs/OccupancyGrid (data copied into an (height, width) array).

    Raises:
        ValueError: data does not have width x height cells.
    """
    width, height = int(msg.info.width), int(msg.info.height)
    data = np.asarray(msg.data, dtype=np.int8)
    if data.size != width * height:
        raise ValueError(f'OccupancyGrid has {data.size} cells for {width} x {height}')
    o = msg.info.origin
    return OccupancyMap(data.reshape(height, width).copy(), float(msg.info.resolution),
                        (float(o.position.x), float(o.position.y), yaw_from_quaternion(o.orientation.x, o.orientation.y, o.orientation.z, o.orientation.w)))


def resample(grid: OccupancyMap, resolution: float) -> OccupancyMap:
    """The same area at another cell size: each new cell takes the cell of the old map under
    its centre, or the highest value among the old cells whose centres fall in it (so a wall
    one cell thick survives a coarser map). The origin stays."""
    if math.isclose(resolution, grid.resolution):
        return grid
    scale = grid.resolution / resolution
    height, width = max(1, math.ceil(grid.height * scale)), max(1, math.ceil(grid.width * scale))
    rows = np.minimum(((np.arange(height) + 0.5) / scale).astype(int), grid.height - 1)
    cols = np.minimum(((np.arange(width) + 0.5) / scale).astype(int), grid.width - 1)
    data = grid.data[np.ix_(rows, cols)].astype(np.int16)
    old_rows = np.minimum(((np.arange(grid.height) + 0.5) * scale).astype(int), height - 1)
    old_cols = np.minimum(((np.arange(grid.width) + 0.5) * scale).astype(int), width - 1)
    np.maximum.at(data, (old_rows[:, None], old_cols[None, :]), grid.data.astype(np.int16))
    return OccupancyMap(data.astype(np.int8), float(resolution), grid.origin)
