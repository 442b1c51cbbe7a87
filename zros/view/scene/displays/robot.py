"""RobotModel: the URDF from /robot_description (std_msgs/String, latched), each link's visuals
(box, cylinder, sphere; meshes when the file can be loaded) posed with TF, as RViz draws it."""
from __future__ import annotations

from typing import Any

import numpy as np

from zros.view.scene.displays.base import ERROR, OK, WARN, Display, slug
from zros.view.scene.frames import FrameError
from zros.view.scene.geometry import IDENTITY, Transform, wxyz

__all__ = ['RobotModelDisplay', 'visual_rgb']

_DEFAULT_RGB = (200, 200, 200)


def visual_rgb(visual: Any, materials: Any) -> tuple[tuple[int, int, int], float]:
    """RGB (0..255) and alpha of a URDF visual: its own colour, else its named material's."""
    material = visual.material
    rgba = material.rgba if material is not None else None
    if rgba is None and material is not None and material.name in materials:
        rgba = materials[material.name].rgba
    if rgba is None:
        return _DEFAULT_RGB, 1.0
    return (int(round(rgba[0] * 255)), int(round(rgba[1] * 255)), int(round(rgba[2] * 255))), float(rgba[3])


class RobotModelDisplay(Display):
    """Draws the robot once per description; each tick moves the links to where TF puts them."""

    kind = 'RobotModel'
    msg_types = ('std_msgs/msg/String',)
    max_rate = 30.0
    placed_at_stamp = False
    defaults = {'alpha': 1.0}

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self.robot: Any = None
        self.links: dict[str, Any] = {}
        self.problems: list[str] = []

    def qos(self) -> Any:
        from zros.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
        return QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                          durability=DurabilityPolicy.TRANSIENT_LOCAL)

    def place(self, frame: str, stamp_ns: int) -> Transform:
        return IDENTITY           # the description has no header; links are placed one by one

    def draw(self, msg: Any, pose: Transform) -> None:
        from zros.urdf import URDFError, parse_urdf
        try:
            robot = parse_urdf(msg.data)
        except URDFError as exc:
            raise ValueError(f'bad robot description: {exc}') from None
        for node in self.links.values():
            node.remove()
        self.links.clear()
        self.problems = []
        self.robot = robot
        alpha = float(self.options['alpha'])
        for name, link in robot.links.items():
            node = self.ctx.scene.add_frame(f'{self.root.name}/{slug(name)}', show_axes=False, visible=False)
            self.links[name] = node
            for index, visual in enumerate(link.visuals):
                try:
                    self._visual(f'{node.name}/v{index}', visual, robot.materials, alpha)
                except (OSError, ValueError) as exc:
                    self.problems.append(f'{name}: {exc}')
        self.refresh(0.0)

    def _visual(self, name: str, visual: Any, materials: Any, alpha: float) -> None:
        from zros.urdf import Box, Cylinder, Mesh, Sphere
        tx, ty, tz, qx, qy, qz, qw = visual.origin.transform()
        pose = {'position': (tx, ty, tz), 'wxyz': (qw, qx, qy, qz)}
        rgb, opacity = visual_rgb(visual, materials)
        opacity *= alpha
        style = {'opacity': opacity if opacity < 1.0 else None, 'cast_shadow': False, 'receive_shadow': False}
        scene = self.ctx.scene
        geometry = visual.geometry
        if isinstance(geometry, Box):
            scene.add_box(name, rgb, tuple(geometry.size), flat_shading=False, **style, **pose)
        elif isinstance(geometry, Cylinder):
            scene.add_cylinder(name, geometry.radius, geometry.length, rgb, **style, **pose)
        elif isinstance(geometry, Sphere):
            scene.add_icosphere(name, geometry.radius, rgb, **style, **pose)
        elif isinstance(geometry, Mesh):
            from zros.view.scene.meshes import load_mesh
            mesh = load_mesh(geometry.filename)
            scene.add_mesh_simple(name, np.asarray(mesh.vertices, dtype=np.float32),
                                  np.asarray(mesh.faces, dtype=np.uint32), color=rgb, scale=tuple(geometry.scale),
                                  **style, **pose)
        else:
            raise ValueError(f'unknown geometry {type(geometry).__name__}')

    def refresh(self, now: float) -> None:
        if self.robot is None:
            return
        missing = []
        for name, node in self.links.items():
            try:
                pose = self.ctx.frames.lookup(self.ctx.fixed_frame, name) if self.ctx.frames is not None \
                    else (IDENTITY if name == self.ctx.fixed_frame else None)
                if pose is None:
                    raise FrameError('TF is not available')
            except FrameError:
                node.visible = False
                missing.append(name)
                continue
            node.position = pose.translation
            node.wxyz = wxyz(pose.rotation)
            node.visible = self.enabled
        if missing and len(missing) == len(self.links):
            self._set_status(ERROR, f'No transform from [{missing[0]}] to [{self.ctx.fixed_frame}] '
                                    f'(none of the {len(missing)} links can be placed)')
        elif missing:
            self._set_status(WARN, f'No transform from [{missing[0]}] to [{self.ctx.fixed_frame}]'
                                   + (f' (and {len(missing) - 1} more links)' if len(missing) > 1 else ''))
        elif self.problems:
            self._set_status(WARN, f'{len(self.links)} links; not drawn: ' + '; '.join(self.problems[:2]))
        else:
            self._set_status(OK, f'{self.robot.name}: {len(self.links)} links')

    def describe(self, msg: Any) -> str:
        return self.status.text

    def expects_stream(self) -> bool:
        return False

    def set_option(self, name: str, value: Any) -> None:
        self.options[name] = value
        self.redraw()
