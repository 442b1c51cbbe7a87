"""URDF robot descriptions as plain, immutable Python data.

What robot_state_publisher needs (joints: type, parent, child, origin, axis, limits, mimic),
what a scene view needs to draw the robot (links' visuals: geometry, origin, colour) and what
navigation needs for the robot's outline (`Robot.footprint()`). Meshes stay references
(`Mesh.filename`, resolvable with `resolve_package_uri`); nothing is loaded.

    robot = parse_urdf(text)                  # URDFError names the element on bad input
    robot.joints['wheel_left_joint'].transform(0.3)   # 7-tuple (x, y, z, qx, qy, qz, qw)
    robot.link_poses({'wheel_left_joint': 0.3})       # every link's pose in the root link
    robot.footprint('base_footprint')                  # (N, 2) convex outline [m]
"""
from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field
from pathlib import Path
from typing import Mapping, Union

import numpy as np

from zros.errors import ZrosError
from zros.tf2_ros.transform_math import IDENTITY, Transform, compose, to_matrix
from zros.tf_transformations import quaternion_about_axis, quaternion_from_euler

__all__ = ['URDFError', 'Origin', 'Box', 'Cylinder', 'Sphere', 'Mesh', 'Geometry', 'Material', 'Visual',
           'Collision', 'Link', 'Limit', 'Mimic', 'Joint', 'Robot', 'parse_urdf', 'load_urdf',
           'resolve_package_uri', 'JOINT_TYPES', 'MOVING_JOINT_TYPES']

JOINT_TYPES = ('fixed', 'continuous', 'revolute', 'prismatic', 'floating', 'planar')
MOVING_JOINT_TYPES = ('continuous', 'revolute', 'prismatic')


class URDFError(ZrosError):
    """A robot description that cannot be used; the message names the element at fault."""


@dataclass(frozen=True)
class Origin:
    """A pose in the parent's frame: translation xyz [m], then fixed-axis roll, pitch, yaw [rad]."""
    xyz: tuple[float, float, float] = (0.0, 0.0, 0.0)
    rpy: tuple[float, float, float] = (0.0, 0.0, 0.0)

    def transform(self) -> Transform:
        return (*self.xyz, *map(float, quaternion_from_euler(*self.rpy)))


@dataclass(frozen=True)
class Box:
    size: tuple[float, float, float]          # full extents along x, y, z [m]


@dataclass(frozen=True)
class Cylinder:
    radius: float                             # [m]
    length: float                             # along the shape's own z axis [m]


@dataclass(frozen=True)
class Sphere:
    radius: float                             # [m]


@dataclass(frozen=True)
class Mesh:
    filename: str                             # usually package://pkg/path/file.stl
    scale: tuple[float, float, float] = (1.0, 1.0, 1.0)


Geometry = Union[Box, Cylinder, Sphere, Mesh]


@dataclass(frozen=True)
class Material:
    name: str = ''
    rgba: tuple[float, float, float, float] | None = None   # each 0..1
    texture: str = ''


@dataclass(frozen=True)
class Visual:
    geometry: Geometry
    origin: Origin = Origin()
    material: Material | None = None
    name: str = ''


@dataclass(frozen=True)
class Collision:
    geometry: Geometry
    origin: Origin = Origin()
    name: str = ''


@dataclass(frozen=True)
class Link:
    name: str
    visuals: tuple[Visual, ...] = ()
    collisions: tuple[Collision, ...] = ()
    mass: float | None = None                 # [kg], from <inertial>


@dataclass(frozen=True)
class Limit:
    lower: float = 0.0
    upper: float = 0.0
    effort: float = 0.0
    velocity: float = 0.0


@dataclass(frozen=True)
class Mimic:
    joint: str
    multiplier: float = 1.0
    offset: float = 0.0


@dataclass(frozen=True)
class Joint:
    name: str
    type: str                                 # one of JOINT_TYPES
    parent: str
    child: str
    origin: Origin = Origin()
    axis: tuple[float, float, float] = (1.0, 0.0, 0.0)
    limit: Limit | None = None
    mimic: Mimic | None = None

    @property
    def moving(self) -> bool:
        return self.type in MOVING_JOINT_TYPES

    def transform(self, position: float = 0.0) -> Transform:
        """The child link's pose in the parent link with the joint at `position` ([rad] for
        revolute and continuous joints, [m] for prismatic ones)."""
        base = self.origin.transform()
        if self.type in ('continuous', 'revolute'):
            motion = (0.0, 0.0, 0.0, *map(float, quaternion_about_axis(position, self.axis)))
        elif self.type == 'prismatic':
            motion = (self.axis[0] * position, self.axis[1] * position, self.axis[2] * position, 0.0, 0.0, 0.0, 1.0)
        else:
            return base
        return compose(base, motion)


@dataclass(frozen=True)
class Robot:
    name: str
    links: Mapping[str, Link]
    joints: Mapping[str, Joint]
    materials: Mapping[str, Material] = field(default_factory=dict)

    @property
    def root(self) -> str:
        """The one link that is nobody's child."""
        children = {j.child for j in self.joints.values()}
        return next(name for name in self.links if name not in children)

    def child_joints(self, link: str) -> list[Joint]:
        return [j for j in self.joints.values() if j.parent == link]

    def joint_position(self, joint: Joint, positions: Mapping[str, float]) -> float:
        """A joint's position from `positions`, following <mimic> (0 when not given)."""
        if joint.mimic is not None:
            leader = self.joints.get(joint.mimic.joint)
            base = self.joint_position(leader, positions) if leader is not None else 0.0
            return joint.mimic.multiplier * base + joint.mimic.offset
        return float(positions.get(joint.name, 0.0))

    def link_poses(self, positions: Mapping[str, float] | None = None, root: str | None = None) -> dict[str, Transform]:
        """Every link's pose in `root` (default: the root link), joints at `positions` (0 for
        any joint not given)."""
        positions = positions or {}
        start = root or self.root
        poses = {start: IDENTITY}
        stack = [start]
        while stack:
            link = stack.pop()
            for joint in self.child_joints(link):
                poses[joint.child] = compose(poses[link], joint.transform(self.joint_position(joint, positions)))
                stack.append(joint.child)
        return poses

    def footprint(self, frame: str = 'base_footprint', *, samples: int = 32) -> np.ndarray:
        """The robot's outline on the ground: the convex hull, in `frame` (a link), of every
        collision shape below that link projected onto its x-y plane, joints at 0.

        Returns:
            (N, 2) array of hull corners [m], counter-clockwise. Meshes are skipped (their
            size is unknown without loading them); links with no collision shape use their visuals.
        """
        if frame not in self.links:
            raise URDFError(f"footprint: no link named '{frame}' (links: {', '.join(self.links)})")
        points = []
        for link_name, pose in self.link_poses(root=frame).items():
            link = self.links[link_name]
            shapes = link.collisions or link.visuals
            for shape in shapes:
                outline = _shape_points(shape.geometry, samples)
                if outline is None:
                    continue
                m = to_matrix(compose(pose, shape.origin.transform()))
                points.append((m[:3, :3] @ outline.T).T[:, :2] + m[:2, 3])
        if not points:
            raise URDFError(f"footprint: no box, cylinder or sphere collision shape at or below link '{frame}'")
        return _convex_hull(np.vstack(points))


def _shape_points(geometry: Geometry, samples: int) -> np.ndarray | None:
    """(M, 3) points on the shape's surface, in the shape's frame, that span its projection."""
    if isinstance(geometry, Box):
        half = np.asarray(geometry.size) / 2.0
        corners = np.array(np.meshgrid([-1, 1], [-1, 1], [-1, 1])).reshape(3, -1).T
        return corners * half
    angles = np.linspace(0.0, 2.0 * math.pi, samples, endpoint=False)
    if isinstance(geometry, Cylinder):
        ring = np.column_stack([geometry.radius * np.cos(angles), geometry.radius * np.sin(angles)])
        ends = [np.column_stack([ring, np.full(samples, z)]) for z in (-geometry.length / 2, geometry.length / 2)]
        return np.vstack(ends)
    if isinstance(geometry, Sphere):  # the equator and two meridians reach every side of its shadow
        r = geometry.radius
        circle = np.column_stack([np.cos(angles), np.sin(angles), np.zeros(samples)])
        return r * np.vstack([circle, circle[:, [0, 2, 1]], circle[:, [2, 0, 1]]])
    return None


def _convex_hull(points: np.ndarray) -> np.ndarray:
    """Counter-clockwise hull of 2-D points (Andrew's monotone chain)."""
    pts = np.unique(np.round(points, 12), axis=0)
    if len(pts) < 3:
        return pts

    def half(seq: np.ndarray) -> list:
        out: list = []
        for p in seq:
            while len(out) >= 2 and ((out[-1][0] - out[-2][0]) * (p[1] - out[-2][1])
                                     - (out[-1][1] - out[-2][1]) * (p[0] - out[-2][0])) <= 0:
                out.pop()
            out.append(p)
        return out
    lower, upper = half(pts), half(pts[::-1])
    return np.array(lower[:-1] + upper[:-1])


# -- parsing --------------------------------------------------------------------------------------
def _describe(element: ET.Element) -> str:
    name = element.get('name')
    return f"<{element.tag} name='{name}'>" if name is not None else f'<{element.tag}>'


def _floats(text: str | None, count: int, where: str, attribute: str, default: tuple | None = None) -> tuple:
    if text is None:
        if default is None:
            raise URDFError(f'{where}: missing attribute {attribute}')
        return default
    try:
        values = tuple(float(v) for v in text.split())
    except ValueError:
        raise URDFError(f"{where}: {attribute}='{text}' is not {count} number(s)") from None
    if len(values) != count:
        raise URDFError(f"{where}: {attribute}='{text}' must have {count} number(s)")
    return values


def _origin(parent: ET.Element, where: str) -> Origin:
    element = parent.find('origin')
    if element is None:
        return Origin()
    return Origin(_floats(element.get('xyz'), 3, f'{where} <origin>', 'xyz', (0.0, 0.0, 0.0)),
                  _floats(element.get('rpy'), 3, f'{where} <origin>', 'rpy', (0.0, 0.0, 0.0)))


def _geometry(parent: ET.Element, where: str) -> Geometry:
    element = parent.find('geometry')
    if element is None or len(element) == 0:
        raise URDFError(f'{where}: missing <geometry> with a box, cylinder, sphere or mesh')
    shape = element[0]
    here = f'{where} <{shape.tag}>'
    if shape.tag == 'box':
        return Box(_floats(shape.get('size'), 3, here, 'size'))
    if shape.tag == 'cylinder':
        return Cylinder(_floats(shape.get('radius'), 1, here, 'radius')[0],
                        _floats(shape.get('length'), 1, here, 'length')[0])
    if shape.tag == 'sphere':
        return Sphere(_floats(shape.get('radius'), 1, here, 'radius')[0])
    if shape.tag == 'mesh':
        filename = shape.get('filename')
        if not filename:
            raise URDFError(f'{here}: missing attribute filename')
        return Mesh(filename, _floats(shape.get('scale'), 3, here, 'scale', (1.0, 1.0, 1.0)))
    raise URDFError(f'{where}: unknown geometry <{shape.tag}> (expected box, cylinder, sphere or mesh)')


def _material(element: ET.Element | None, where: str, named: dict[str, Material]) -> Material | None:
    if element is None:
        return None
    name = element.get('name', '')
    color = element.find('color')
    texture = element.find('texture')
    if color is None and texture is None:
        return named.get(name, Material(name))
    rgba = _floats(color.get('rgba'), 4, f'{where} <color>', 'rgba') if color is not None else None
    return Material(name, rgba, texture.get('filename', '') if texture is not None else '')


def _link(element: ET.Element, named: dict[str, Material]) -> Link:
    where = _describe(element)
    visuals = tuple(Visual(_geometry(v, f'{where} <visual>'), _origin(v, f'{where} <visual>'),
                           _material(v.find('material'), f'{where} <visual>', named), v.get('name', ''))
                    for v in element.findall('visual'))
    collisions = tuple(Collision(_geometry(c, f'{where} <collision>'), _origin(c, f'{where} <collision>'),
                                 c.get('name', ''))
                       for c in element.findall('collision'))
    mass_element = element.find('inertial/mass')
    mass = _floats(mass_element.get('value'), 1, f'{where} <mass>', 'value')[0] if mass_element is not None else None
    return Link(element.get('name'), visuals, collisions, mass)


def _joint(element: ET.Element) -> Joint:
    where = _describe(element)
    kind = element.get('type')
    if kind not in JOINT_TYPES:
        raise URDFError(f"{where}: type '{kind}' is not one of {', '.join(JOINT_TYPES)}")
    ends = {}
    for end in ('parent', 'child'):
        tag = element.find(end)
        if tag is None or not tag.get('link'):
            raise URDFError(f'{where}: missing <{end} link="..."/>')
        ends[end] = tag.get('link')
    axis_element = element.find('axis')
    axis = _floats(axis_element.get('xyz') if axis_element is not None else None, 3, f'{where} <axis>', 'xyz',
                   (1.0, 0.0, 0.0))
    if kind in MOVING_JOINT_TYPES:
        norm = math.sqrt(sum(a * a for a in axis))
        if norm == 0.0:
            raise URDFError(f'{where} <axis>: xyz must not be zero')
        axis = tuple(a / norm for a in axis)
    limit = None
    limit_element = element.find('limit')
    if limit_element is not None:
        get = lambda name: _floats(limit_element.get(name), 1, f'{where} <limit>', name, (0.0,))[0]  # noqa: E731
        limit = Limit(get('lower'), get('upper'), get('effort'), get('velocity'))
    elif kind in ('revolute', 'prismatic'):
        raise URDFError(f'{where}: a {kind} joint needs <limit lower upper effort velocity>')
    mimic = None
    mimic_element = element.find('mimic')
    if mimic_element is not None:
        if not mimic_element.get('joint'):
            raise URDFError(f'{where} <mimic>: missing attribute joint')
        mimic = Mimic(mimic_element.get('joint'),
                      _floats(mimic_element.get('multiplier'), 1, f'{where} <mimic>', 'multiplier', (1.0,))[0],
                      _floats(mimic_element.get('offset'), 1, f'{where} <mimic>', 'offset', (0.0,))[0])
    return Joint(element.get('name'), kind, ends['parent'], ends['child'], _origin(element, where), axis, limit, mimic)


def parse_urdf(text: str) -> Robot:
    """Parse URDF XML (what robot_state_publisher's `robot_description` holds).

    Raises:
        URDFError: one line naming the element (or the XML line) at fault.
    """
    if not isinstance(text, str) or not text.strip():
        raise URDFError('the robot description is empty')
    try:
        root = ET.fromstring(text)
    except ET.ParseError as exc:
        raise URDFError(f'the robot description is not well-formed XML: {exc}') from None
    if root.tag != 'robot':
        raise URDFError(f'the root element is <{root.tag}>, expected <robot>')
    if any(isinstance(child.tag, str) and 'wiki/xacro}' in child.tag for child in root.iter()):
        raise URDFError('the description still contains xacro elements: run it through xacro first')
    named: dict[str, Material] = {}
    for element in root.findall('material'):
        material = _material(element, _describe(element), named)
        named[material.name] = material
    links: dict[str, Link] = {}
    for element in root.findall('link'):
        if not element.get('name'):
            raise URDFError('<link> without a name attribute')
        if element.get('name') in links:
            raise URDFError(f"{_describe(element)}: a link of that name is defined twice")
        links[element.get('name')] = _link(element, named)
    if not links:
        raise URDFError(f"<robot name='{root.get('name', '')}'> has no <link>")
    joints: dict[str, Joint] = {}
    for element in root.findall('joint'):
        if not element.get('name'):
            raise URDFError('<joint> without a name attribute')
        joint = _joint(element)
        if joint.name in joints:
            raise URDFError(f"{_describe(element)}: a joint of that name is defined twice")
        for end in (joint.parent, joint.child):
            if end not in links:
                raise URDFError(f"{_describe(element)}: link '{end}' is not defined")
        joints[joint.name] = joint
    parents: dict[str, str] = {}
    for joint in joints.values():
        if joint.child in parents:
            raise URDFError(f"<joint name='{joint.name}'>: link '{joint.child}' already has parent joint "
                            f"'{parents[joint.child]}'")
        parents[joint.child] = joint.name
    roots = [name for name in links if name not in parents]
    if len(roots) != 1:
        raise URDFError('the links do not form one tree: ' + (f"roots are {', '.join(roots)}" if roots
                                                             else 'the joints form a loop'))
    for joint in joints.values():
        if joint.mimic is not None and joint.mimic.joint not in joints:
            raise URDFError(f"<joint name='{joint.name}'> <mimic>: joint '{joint.mimic.joint}' is not defined")
    return Robot(root.get('name', ''), links, joints, named)


def load_urdf(path: str | Path) -> Robot:
    """Parse a .urdf file, or a .xacro file after expanding it."""
    path = Path(path)
    if path.suffix == '.xacro':
        from zros.urdf.xacro import process_file
        return parse_urdf(process_file(path))
    try:
        text = path.read_text()
    except OSError as exc:
        raise URDFError(f'cannot read {path}: {exc.strerror}') from None
    return parse_urdf(text)


def resolve_package_uri(uri: str) -> Path:
    """`package://pkg/dir/file` or `file:///abs/path` -> a path on disk (not checked to exist)."""
    if uri.startswith('package://'):
        package, _, rest = uri[len('package://'):].partition('/')
        from zros.ament_index_python.packages import get_package_share_path
        return get_package_share_path(package) / rest
    if uri.startswith('file://'):
        return Path(uri[len('file://'):])
    return Path(uri)
