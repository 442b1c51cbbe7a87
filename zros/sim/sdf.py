"""SDF worlds: a Gazebo classic `.world` file, cut at the lidar's height into a zros.sim World.

    world = load_sdf_world('worlds/turtlebot3_world.world')          # models found on the model path
    world = parse_sdf_world(text, model_path=[Path('models')], height=0.18)

The TurtleBot3 meets a 3D world in one plane only (zros.sim.world), so every collision geometry
of every model is cut by the horizontal plane `height` metres above the ground (0.18 m: the
burger's lidar is at 0.182 m, the waffle's at 0.132 m):
- `box`, a `cylinder` lying on its side, any tilted shape: the exact section of the convex solid
  (a cylinder as a 32-sided prism), a filled polygon;
- an upright `cylinder`, a `sphere`: a circle;
- `polyline`: its polygon, if the extrusion reaches the plane;
- `mesh` (`.dae`, `.stl`, `.obj`, read with trimesh, and pycollada for COLLADA; the file's unit
  applies, then `<scale>`): the segments where the plane cuts its triangles, walls of no thickness;
- `plane` (the ground) has no section and is left out; so are shapes the plane misses.
Poses (`x y z roll pitch yaw`, roll, pitch and yaw about the fixed axes) compose from the world
through nested models, links and collisions; `<include><uri>model://NAME</uri>` reads the
model folder NAME on the model path (`model.config` names its SDF file), with the include's
`<pose>` and `<static>` in place of the model's own. A static model (`<static>` true, or inside
a static model) is fixed; a non-static one (Gazebo's default) whose sections are all areas (box,
cylinder, sphere, polyline) is a pushable `Body` with its links' mass, and one with a mesh
section stays fixed. `model://ground_plane` and `model://sun` need no folder: they hold nothing
the plane cuts.

What cannot be used is left out with one warning each (`on_warning`): a model or mesh not on the
model path, a Gazebo Fuel URL (zros downloads nothing), a geometry kind zros does not cut
(capsule, ellipsoid, heightmap). Malformed XML or numbers stop with one line, `file:line: what`.

The model path (`default_model_path`) is Gazebo's: the folders of GAZEBO_MODEL_PATH (Gazebo Sim:
GZ_SIM_RESOURCE_PATH), then the
`models/` folder of every package the package index knows (turtlebot3_gazebo's, as its
package.xml exports it to Gazebo).
"""
from __future__ import annotations

import math
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable, Iterable, Iterator
from xml.parsers import expat

import numpy as np

from zros.sim.world import Body, World
from zros.sim.world_file import WorldFileError

__all__ = ['SdfError', 'XmlElement', 'parse_xml', 'numbers', 'flag', 'pose_matrix', 'default_model_path', 'find_model',
           'parse_sdf_world', 'load_sdf_world', 'DEFAULT_SLICE_HEIGHT']

DEFAULT_SLICE_HEIGHT = 0.18     # [m] above the ground: the TurtleBot3 burger's lidar plane
_CYLINDER_SIDES = 32
#: Models of Gazebo's own database that hold nothing a horizontal plane above the ground cuts.
_BUILTIN_MODELS = ('ground_plane', 'sun')
_UNSUPPORTED = ('capsule', 'ellipsoid', 'heightmap', 'image')

Warn = Callable[[str], None]


class SdfError(WorldFileError):
    """An SDF or URDF file that cannot be read; the message is `file:line: what`."""


@dataclass
class XmlElement:
    """One element of an XML file, with the line it starts on (for one-line errors)."""
    tag: str
    attrib: dict[str, str]
    line: int
    children: list['XmlElement'] = field(default_factory=list)
    text: str = ''

    def find(self, tag: str) -> 'XmlElement | None':
        return next((child for child in self.children if child.tag == tag), None)

    def findall(self, tag: str) -> list['XmlElement']:
        return [child for child in self.children if child.tag == tag]

    def findtext(self, tag: str, default: str = '') -> str:
        child = self.find(tag)
        return child.text.strip() if child is not None else default

    def iter(self, tag: str) -> Iterator['XmlElement']:
        """This element and every descendant named `tag`, depth first."""
        if self.tag == tag:
            yield self
        for child in self.children:
            yield from child.iter(tag)


def parse_xml(text: str, source: str) -> XmlElement:
    """The root element of an XML document (stdlib expat); SdfError `source:line: ...` if malformed."""
    parser = expat.ParserCreate()
    stack: list[XmlElement] = []
    roots: list[XmlElement] = []

    def start(tag: str, attrib: dict[str, str]) -> None:
        element = XmlElement(tag, attrib, parser.CurrentLineNumber)
        (stack[-1].children if stack else roots).append(element)
        stack.append(element)

    def end(tag: str) -> None:
        stack.pop()

    def data(chunk: str) -> None:
        if stack:
            stack[-1].text += chunk
    parser.StartElementHandler, parser.EndElementHandler, parser.CharacterDataHandler = start, end, data
    try:
        parser.Parse(text, True)
    except expat.ExpatError as exc:
        raise SdfError(f'{source}:{exc.lineno}: invalid XML: {expat.ErrorString(exc.code)}') from None
    return roots[0]


def numbers(element: XmlElement, count: int, source: str) -> list[float]:
    """The `count` numbers of an element's text (`<size>1 2 3</size>`); SdfError naming the line."""
    words = element.text.split()
    try:
        values = [float(word) for word in words]
    except ValueError:
        values = []
    if len(values) != count or not all(math.isfinite(v) for v in values):
        raise SdfError(f"{source}:{element.line}: <{element.tag}> needs {count} finite numbers, got "
                       f"'{element.text.strip()}'")
    return values


def pose_matrix(x: float, y: float, z: float, roll: float, pitch: float, yaw: float) -> np.ndarray:
    """The 4x4 transform of an SDF/URDF pose: rotation Rz(yaw) Ry(pitch) Rx(roll), then translation."""
    cr, sr, cp, sp, cy, sy = (math.cos(roll), math.sin(roll), math.cos(pitch), math.sin(pitch),
                              math.cos(yaw), math.sin(yaw))
    matrix = np.eye(4)
    matrix[:3, :3] = [[cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
                      [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
                      [-sp, cp * sr, cp * cr]]
    matrix[:3, 3] = (x, y, z)
    return matrix


def _pose(parent: XmlElement, source: str) -> np.ndarray:
    """The transform of an element's `<pose>` child (identity without one)."""
    element = parent.find('pose')
    if element is None or not element.text.strip():
        return np.eye(4)
    return pose_matrix(*numbers(element, 6, source))


# -- the model path -------------------------------------------------------------------------------
#: Where Gazebo classic and Gazebo Sim (Harmonic; Fortress's name) look for `model://` folders.
MODEL_PATH_VARIABLES = ('GAZEBO_MODEL_PATH', 'GZ_SIM_RESOURCE_PATH', 'IGN_GAZEBO_RESOURCE_PATH')


def default_model_path() -> list[Path]:
    """The folders of GAZEBO_MODEL_PATH, GZ_SIM_RESOURCE_PATH and IGN_GAZEBO_RESOURCE_PATH, then
    the `models/` folder of every indexed package."""
    folders = [Path(p).expanduser() for variable in MODEL_PATH_VARIABLES
               for p in os.environ.get(variable, '').split(os.pathsep) if p]
    from zros.ament_index_python.packages import package_directories
    folders += [share / 'models' for share in package_directories().values() if (share / 'models').is_dir()]
    return folders


def find_model(name: str, model_path: Iterable[Path]) -> Path | None:
    """The folder of model `name` (`<folder>/<name>/` holding model.config or model.sdf), or None.
    A model may sit one level deeper (turtlebot3_gazebo's `models/turtlebot3_autorace_2020/*`)."""
    for folder in model_path:
        for candidate in (Path(folder) / name, *Path(folder).glob(f'*/{name}')):
            if (candidate / 'model.config').is_file() or (candidate / 'model.sdf').is_file():
                return candidate
    return None


def model_sdf_file(folder: Path) -> Path:
    """The SDF file of a model folder: the newest `<sdf version=...>` its model.config lists,
    else `model.sdf`."""
    config = folder / 'model.config'
    if config.is_file():
        try:
            root = parse_xml(config.read_text(encoding='utf-8'), str(config))
        except (SdfError, OSError, UnicodeDecodeError):
            root = None
        if root is not None:
            listed = [(_version(e.attrib.get('version', '0')), e.text.strip()) for e in root.findall('sdf')]
            listed = [(version, name) for version, name in listed if name and (folder / name).is_file()]
            if listed:
                return folder / max(listed)[1]
    return folder / 'model.sdf'


def _version(text: str) -> tuple[int, ...]:
    return tuple(int(part) for part in text.split('.') if part.isdigit())


# -- the world ---------------------------------------------------------------------------------
def load_sdf_world(path: str | os.PathLike, *, model_path: Iterable[Path] | None = None,
                   height: float = DEFAULT_SLICE_HEIGHT, on_warning: Warn | None = None) -> World:
    """The World of an SDF world file, cut at `height` [m]; `model_path` defaults to Gazebo's."""
    path = Path(path)
    try:
        text = path.read_text(encoding='utf-8')
    except (OSError, UnicodeDecodeError) as exc:
        raise SdfError(f'{path}: cannot read: {exc}') from None
    return parse_sdf_world(text, source=path, model_path=default_model_path() if model_path is None else model_path,
                           height=height, on_warning=on_warning)


def parse_sdf_world(text: str, *, source: str | os.PathLike = '<string>', model_path: Iterable[Path] = (),
                    height: float = DEFAULT_SLICE_HEIGHT, on_warning: Warn | None = None) -> World:
    """The World of an SDF document's text: its `<world>` (or, for a model file, its models)."""
    slicer = _Slicer(list(model_path), height, on_warning or (lambda message: None))
    source_text = os.fspath(source)
    root = parse_xml(text, source_text)
    if root.tag != 'sdf':
        raise SdfError(f'{source_text}:{root.line}: expected an <sdf> document, got <{root.tag}>')
    world = root.find('world')
    base = Path(source_text).parent
    if world is not None:
        name = world.attrib.get('name', Path(source_text).stem)
        slicer.entities(world, np.eye(4), source_text, base, False)
    else:
        name = Path(source_text).stem
        slicer.entities(root, np.eye(4), source_text, base, False)
    return World(name=name, polygons=tuple(slicer.polygons), circles=np.array(slicer.circles).reshape(-1, 3),
                 segments=np.array(slicer.segments).reshape(-1, 4),
                 source=None if source_text.startswith('<') else Path(source_text), bodies=tuple(slicer.bodies))


class _Slicer:
    """Walks models, links and collisions, and keeps what the plane `height` cuts out of them."""

    def __init__(self, model_path: list[Path], height: float, warn: Warn) -> None:
        self.model_path, self.height, self.warn = model_path, height, warn
        self.polygons: list[tuple[np.ndarray, ...]] = []
        self.circles: list[tuple[float, float, float]] = []
        self.segments: list[np.ndarray] = []
        self.bodies: list[Body] = []
        self._meshes: dict[Path, tuple[np.ndarray, np.ndarray] | None] = {}

    def entities(self, parent: XmlElement, frame: np.ndarray, source: str, base: Path, static: bool) -> None:
        """The models and includes directly under `parent` (a world or a model), in `frame`;
        `static`: the parent is static, and so is everything in it."""
        for child in parent.children:
            if child.tag == 'model':
                self.model(child, frame @ _pose(child, source), source, base, static or _static(child, source))
            elif child.tag == 'include':
                self.include(child, frame, source, base, static)

    def model(self, model: XmlElement, frame: np.ndarray, source: str, base: Path, static: bool) -> None:
        kept = (self.polygons, self.circles, self.segments)
        if not static:       # its sections, apart: a pushable body if they are all areas
            self.polygons, self.circles, self.segments = [], [], []
        for link in model.findall('link'):
            link_frame = frame @ _pose(link, source)
            for collision in link.findall('collision'):
                geometry = collision.find('geometry')
                if geometry is not None:
                    self.geometry(geometry, link_frame @ _pose(collision, source), source, base)
        if not static:
            own = (self.polygons, self.circles, self.segments)
            self.polygons, self.circles, self.segments = kept
            if (own[0] or own[1]) and not own[2]:
                mass = sum(_mass(link, source) for link in model.findall('link'))
                self.bodies.append(Body(model.attrib.get('name', '?'), tuple(loop for shape in own[0] for loop in shape),
                                        np.array(own[1]).reshape(-1, 3), mass))
            else:
                for mine, theirs in zip(kept, own):
                    mine.extend(theirs)
        self.entities(model, frame, source, base, static)

    def include(self, include: XmlElement, frame: np.ndarray, source: str, base: Path, static: bool) -> None:
        uri = include.findtext('uri')
        name = uri.removeprefix('model://').strip('/')
        folder = self._resolve_model(uri, base)
        if folder is None and uri.startswith(('http://', 'https://')):
            self.warn(f"{source}:{include.line}: model '{uri}' is on Gazebo Fuel, and zros downloads nothing: "
                      'left out (put the model in a folder on GZ_SIM_RESOURCE_PATH and include it as model://NAME)')
            return
        if folder is None:
            if name not in _BUILTIN_MODELS:
                self.warn(f"{source}:{include.line}: model '{uri}' not found on the model path "
                          '(GAZEBO_MODEL_PATH, GZ_SIM_RESOURCE_PATH, packages\' models/): left out')
            return
        sdf_file = model_sdf_file(folder)
        try:
            text = sdf_file.read_text(encoding='utf-8')
        except (OSError, UnicodeDecodeError) as exc:
            raise SdfError(f'{source}:{include.line}: cannot read {sdf_file}: {exc}') from None
        root = parse_xml(text, str(sdf_file))
        for model in root.findall('model'):
            own = _pose(include, source) if include.find('pose') is not None else _pose(model, str(sdf_file))
            fixed = _static(include, source) if include.find('static') is not None else _static(model, str(sdf_file))
            self.model(model, frame @ own, str(sdf_file), sdf_file.parent, static or fixed)

    def _resolve_model(self, uri: str, base: Path) -> Path | None:
        if uri.startswith('model://'):
            return find_model(uri.removeprefix('model://').strip('/').split('/')[0], self.model_path)
        folder = Path(uri.removeprefix('file://'))
        folder = folder if folder.is_absolute() else base / folder
        return folder if folder.is_dir() else None

    def _resolve_file(self, uri: str, base: Path) -> Path | None:
        if uri.startswith('model://'):
            name, _, rest = uri.removeprefix('model://').partition('/')
            folder = find_model(name, self.model_path)
            return folder / rest if folder is not None and (folder / rest).is_file() else None
        path = Path(uri.removeprefix('file://'))
        path = path if path.is_absolute() else base / path
        return path if path.is_file() else None

    # -- geometry ----------------------------------------------------------------------------
    def geometry(self, geometry: XmlElement, frame: np.ndarray, source: str, base: Path) -> None:
        for shape in geometry.children:
            kind = shape.tag
            if kind == 'box':
                size = numbers(_child(shape, 'size', source), 3, source)
                corners = np.array([[sx, sy, sz] for sx in (-.5, .5) for sy in (-.5, .5) for sz in (-.5, .5)]) * size
                self.convex(_apply(frame, corners))
            elif kind == 'cylinder':
                radius = _positive(shape, 'radius', source)
                length = _positive(shape, 'length', source)
                self.cylinder(frame, radius, length)
            elif kind == 'sphere':
                radius = _positive(shape, 'radius', source)
                centre = frame[:3, 3]
                depth = abs(centre[2] - self.height)
                if depth < radius:
                    self.circles.append((centre[0], centre[1], math.sqrt(radius ** 2 - depth ** 2)))
            elif kind == 'polyline':
                self.polyline(shape, frame, source)
            elif kind == 'mesh':
                self.mesh(shape, frame, source, base)
            elif kind in _UNSUPPORTED:
                self.warn(f'{source}:{shape.line}: <{kind}> geometry is not cut by zros: left out')
            # <plane> (the ground) and <empty/> have no section.

    def cylinder(self, frame: np.ndarray, radius: float, length: float) -> None:
        axis, centre = frame[:3, 2], frame[:3, 3]
        if abs(axis[2]) > 1.0 - 1e-9:      # upright: a circle, if the plane crosses it
            if abs(centre[2] - self.height) < length / 2:
                self.circles.append((centre[0], centre[1], radius))
            return
        angles = 2 * math.pi * np.arange(_CYLINDER_SIDES) / _CYLINDER_SIDES
        ring = np.column_stack([radius * np.cos(angles), radius * np.sin(angles)])
        prism = np.vstack([np.column_stack([ring, np.full(len(ring), z)]) for z in (-length / 2, length / 2)])
        self.convex(_apply(frame, prism))

    def convex(self, points: np.ndarray) -> None:
        """Keep the section of the convex hull of `points` (N, 3) [world]: every segment between
        two of its points lies inside it, so the plane's crossings of all of them span the section."""
        z = points[:, 2] - self.height
        below, above = points[z < 0], points[z >= 0]
        if not len(below) or not len(above):
            return
        zb, za = z[z < 0][:, None], z[z >= 0][None, :]
        t = zb / (zb - za)                                           # (B, A) in (0, 1]
        crossings = below[:, None, :2] + t[..., None] * (above[None, :, :2] - below[:, None, :2])
        loop = _convex_hull(crossings.reshape(-1, 2))
        if len(loop) >= 3 and _area(loop) > 1e-10:
            self.polygons.append((loop,))

    def polyline(self, shape: XmlElement, frame: np.ndarray, source: str) -> None:
        height = _positive(shape, 'height', source)
        if not 0.0 <= self.height - frame[2, 3] <= height:
            return
        points = np.array([numbers(point, 2, source) for point in shape.findall('point')])
        if len(points) >= 3:
            loop = _apply(frame, np.column_stack([points, np.zeros(len(points))]))[:, :2]
            if _area(loop) > 1e-10:
                self.polygons.append((loop,))

    def mesh(self, shape: XmlElement, frame: np.ndarray, source: str, base: Path) -> None:
        uri = shape.findtext('uri')
        path = self._resolve_file(uri, base)
        if path is None:
            self.warn(f"{source}:{shape.line}: mesh '{uri}' not found on the model path: left out")
            return
        if path not in self._meshes:
            self._meshes[path] = _load_mesh(path, f'{source}:{shape.line}', self.warn)
        loaded = self._meshes[path]
        if loaded is None:
            return
        vertices, faces = loaded
        scale_element = shape.find('scale')
        scale = numbers(scale_element, 3, source) if scale_element is not None else [1.0, 1.0, 1.0]
        world = _apply(frame, vertices * scale)
        self.segments.extend(_cut_triangles(world[faces], self.height))


def flag(parent: XmlElement, tag: str, default: bool, source: str) -> bool:
    """A boolean child element `<tag>` (true/1 or false/0), `default` when absent; SdfError otherwise."""
    element = parent.find(tag)
    if element is None:
        return default
    text = element.text.strip().lower()
    if text not in ('true', 'false', '1', '0'):
        raise SdfError(f'{source}:{element.line}: <{tag}> must be true or false, got {element.text.strip()!r}')
    return text in ('true', '1')


def _static(model: XmlElement, source: str) -> bool:
    """A model's (or include's) `<static>`, false when absent (SDF's default)."""
    return flag(model, 'static', False, source)


def _mass(link: XmlElement, source: str) -> float:
    """A link's `<inertial><mass>` [kg]; SDF's default 1 kg without one."""
    inertial = link.find('inertial')
    element = inertial.find('mass') if inertial is not None else None
    if element is None:
        return 1.0
    mass = numbers(element, 1, source)[0]
    if not mass > 0:
        raise SdfError(f'{source}:{element.line}: <mass> must be > 0, got {mass:g}')
    return mass


def _child(parent: XmlElement, tag: str, source: str) -> XmlElement:
    child = parent.find(tag)
    if child is None:
        raise SdfError(f'{source}:{parent.line}: <{parent.tag}> needs a <{tag}>')
    return child


def _positive(parent: XmlElement, tag: str, source: str) -> float:
    child = _child(parent, tag, source)
    value = numbers(child, 1, source)[0]
    if not value > 0:
        raise SdfError(f'{source}:{child.line}: <{tag}> must be > 0, got {value:g}')
    return value


def _apply(frame: np.ndarray, points: np.ndarray) -> np.ndarray:
    return points @ frame[:3, :3].T + frame[:3, 3]


def _area(loop: np.ndarray) -> float:
    return 0.5 * abs(float(np.sum(loop[:, 0] * np.roll(loop[:, 1], -1) - np.roll(loop[:, 0], -1) * loop[:, 1])))


def _convex_hull(points: np.ndarray) -> np.ndarray:
    """Counter-clockwise corners (K, 2) of the convex hull of points (N, 2) (monotone chain)."""
    unique = np.unique(np.round(points, 12), axis=0)
    if len(unique) < 3:
        return unique

    def half(rows: np.ndarray) -> list[np.ndarray]:
        chain: list[np.ndarray] = []
        for p in rows:
            while len(chain) >= 2 and _turn(chain[-2], chain[-1], p) <= 1e-12:
                chain.pop()
            chain.append(p)
        return chain
    lower, upper = half(unique), half(unique[::-1])
    return np.array(lower[:-1] + upper[:-1])


def _turn(a: np.ndarray, b: np.ndarray, c: np.ndarray) -> float:
    """> 0 when a -> b -> c turns counter-clockwise."""
    return float((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))


def _cut_triangles(triangles: np.ndarray, height: float) -> list[np.ndarray]:
    """The segments (x1, y1, x2, y2) where the plane z = height cuts triangles (T, 3, 3)."""
    z = triangles[:, :, 2] - height
    z = np.where(z == 0.0, 1e-12, z)                   # a corner on the plane counts as above it
    above = z > 0
    crossing = above.sum(axis=1) % 3 != 0
    segments = []
    for triangle, dz, up in zip(triangles[crossing], z[crossing], above[crossing]):
        lone = int(np.flatnonzero(up if up.sum() == 1 else ~up)[0])
        ends = []
        for other in ((lone + 1) % 3, (lone + 2) % 3):
            t = dz[lone] / (dz[lone] - dz[other])
            ends.append(triangle[lone, :2] + t * (triangle[other, :2] - triangle[lone, :2]))
        if np.hypot(*(ends[1] - ends[0])) > 1e-9:
            segments.append(np.concatenate(ends))
    return segments


def _load_mesh(path: Path, where: str, warn: Warn) -> tuple[np.ndarray, np.ndarray] | None:
    """(vertices (V, 3) [m], faces (F, 3)) of a mesh file, in metres (the file's unit applied)."""
    try:
        import trimesh
    except ImportError:
        warn(f"{where}: mesh {path.name} needs trimesh (pip install 'zros[sim]'): left out")
        return None
    try:
        mesh = trimesh.load(str(path), force='mesh')
        if mesh.units not in (None, 'm', 'meters', 'meter'):
            mesh.convert_units('m')
    except Exception as exc:  # noqa: BLE001 - trimesh raises many kinds; one warning names the file
        hint = " (COLLADA needs pycollada: pip install 'zros[sim]')" if path.suffix.lower() == '.dae' else ''
        warn(f'{where}: cannot read mesh {path}: {exc}{hint}: left out')
        return None
    if not hasattr(mesh, 'faces') or not len(mesh.faces):
        warn(f'{where}: mesh {path} has no triangles: left out')
        return None
    return np.asarray(mesh.vertices, dtype=np.float64), np.asarray(mesh.faces, dtype=np.int64)
