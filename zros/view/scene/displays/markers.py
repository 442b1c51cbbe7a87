"""Marker and MarkerArray: RViz's marker types, kept by (namespace, id), with DELETE, DELETEALL,
lifetimes and frame-locked markers.

Unlike the other displays every message counts (a Marker message adds or removes one marker),
so messages are queued rather than replaced by the newest.
"""
from __future__ import annotations

import threading
import time
from collections import deque
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from zros.view.scene.convert import MarkerShape, arrow_marker_points, marker_shape, polyline_segments
from zros.view.scene.displays.base import ERROR, OK, WARN, Display, slug, stamp_ns
from zros.view.scene.frames import FrameError
from zros.view.scene.geometry import IDENTITY, pose_transform, wxyz

__all__ = ['MarkerDisplay']

_QUEUE = 10_000
_DELETE, _DELETEALL = 2, 3


@dataclass
class _Marker:
    frame: str
    pose: Any                       # the marker's geometry_msgs/Pose in `frame`
    node: Any                       # the viser frame the geometry hangs from
    children: list[Any] = field(default_factory=list)
    expires_at: float = 0.0         # monotonic time; 0 = never
    frame_locked: bool = False


class MarkerDisplay(Display):
    """RViz's Marker and MarkerArray displays (both message types)."""

    kind = 'Marker'
    msg_types = ('visualization_msgs/msg/Marker', 'visualization_msgs/msg/MarkerArray')
    max_rate = 30.0

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self.markers: dict[tuple[str, int], _Marker] = {}
        self._queue: deque[Any] = deque(maxlen=_QUEUE)
        self._queue_lock = threading.Lock()
        self.problems: dict[tuple[str, int], str] = {}

    def qos(self) -> Any:
        return 100

    def on_message(self, msg: Any) -> None:
        with self._queue_lock:
            self._queue.append(msg)
        self.received += 1
        self._last_message_at = time.monotonic()
        self.ctx.wake.set()

    def tick(self, now: float) -> None:
        if not self.enabled:
            return
        with self._queue_lock:
            batch = list(self._queue)
            self._queue.clear()
        for msg in batch:
            for marker in (msg.markers if hasattr(msg, 'markers') else [msg]):
                self.apply(marker, now)
        self.refresh(now)
        if not batch and not self.markers and self.received == 0:
            self._check_silence(now)
            return
        if self.problems:
            (ns, ident), text = next(iter(self.problems.items()))
            more = f' (and {len(self.problems) - 1} more)' if len(self.problems) > 1 else ''
            self._set_status(ERROR if len(self.problems) == len(self.markers) else WARN,
                             f'{len(self.markers)} markers; [{ns}/{ident}] {text}{more}')
        else:
            self._set_status(OK, f'{len(self.markers)} markers')

    def apply(self, marker: Any, now: float) -> None:
        """Add, replace or delete one marker."""
        key = (str(marker.ns), int(marker.id))
        action = int(marker.action)
        if action == _DELETEALL:
            for existing in list(self.markers):
                self._remove(existing)
            return
        if action == _DELETE:
            self._remove(key)
            return
        self._remove(key)
        self.problems.pop(key, None)
        try:
            shape = marker_shape(marker)
        except ValueError as exc:
            self.problems[key] = str(exc)
            return
        node = self.ctx.scene.add_frame(f'{self.root.name}/{slug(key[0])}_{key[1] & 0xFFFFFFFF}', show_axes=False)
        entry = _Marker(marker.header.frame_id, marker.pose, node, frame_locked=bool(marker.frame_locked))
        lifetime = marker.lifetime.sec + marker.lifetime.nanosec * 1e-9
        entry.expires_at = now + lifetime if lifetime > 0 else 0.0
        self.markers[key] = entry
        try:
            self._place(entry, stamp_ns(marker.header))
        except FrameError as exc:
            self.problems[key] = str(exc)
            node.visible = False
        try:
            entry.children = self._geometry(node.name, shape, marker)
        except (ValueError, OSError) as exc:
            self.problems[key] = str(exc)

    def _place(self, entry: _Marker, stamp_ns: int) -> None:
        frame_pose = self.place(entry.frame, stamp_ns) if entry.frame else IDENTITY
        pose = frame_pose @ pose_transform(entry.pose)
        entry.node.position = pose.translation
        entry.node.wxyz = wxyz(pose.rotation)
        entry.node.visible = True

    def refresh(self, now: float) -> None:
        for key, entry in list(self.markers.items()):
            if entry.expires_at and now >= entry.expires_at:
                self._remove(key)
            elif entry.frame_locked:
                try:
                    self._place(entry, 0)
                except FrameError as exc:
                    self.problems[key] = str(exc)

    def _geometry(self, name: str, shape: MarkerShape, marker: Any) -> list[Any]:
        """The viser nodes of one marker, in the marker's own frame (its pose is the parent's)."""
        scene = self.ctx.scene
        sx, sy, sz = shape.scale
        opacity = shape.alpha if shape.alpha < 1.0 else None
        rgb = shape.rgb
        if shape.kind == 'cube':
            return [scene.add_box(f'{name}/cube', rgb, (sx, sy, sz), opacity=opacity)]
        if shape.kind == 'sphere':
            return [scene.add_icosphere(f'{name}/sphere', 0.5, rgb, scale=(sx, sy, sz), opacity=opacity)]
        if shape.kind == 'cylinder':
            return [scene.add_cylinder(f'{name}/cylinder', 0.5, 1.0, rgb, scale=(sx, sy, sz), opacity=opacity)]
        if shape.kind == 'arrow':
            local = shape._replace(pose=IDENTITY)
            points = arrow_marker_points(local)
            if len(shape.points) >= 2:
                shaft, head, head_length = sx / 2, sy / 2, sz or 0.2 * float(np.linalg.norm(points[0, 1] - points[0, 0]))
            else:
                shaft, head, head_length = sy / 4, sz / 2, 0.23 * sx
            return [scene.add_arrows(f'{name}/arrow', points, rgb, shaft_radius=max(shaft, 1e-3),
                                     head_radius=max(head, 2e-3), head_length=max(head_length, 1e-3))]
        if shape.kind in ('line_strip', 'line_list', 'arrow_strip'):
            if shape.kind == 'line_list':
                pairs = shape.points[:len(shape.points) // 2 * 2].reshape(-1, 2, 3).astype(np.float32)
                colors = shape.colors[:len(pairs) * 2].reshape(-1, 2, 3) if shape.colors is not None else None
            else:
                pairs = polyline_segments(shape.points)
                colors = (np.stack([shape.colors[:-1], shape.colors[1:]], axis=1)
                          if shape.colors is not None and len(shape.colors) > 1 else None)
            if not len(pairs):
                return []
            return [scene.add_line_segments(f'{name}/lines', pairs, colors if colors is not None else rgb,
                                            thickness=max(sx, 1e-3), thickness_units='world')]
        if shape.kind in ('points', 'cube_list', 'sphere_list'):
            if not len(shape.points):
                return []
            colors = shape.colors if shape.colors is not None else np.asarray(rgb, dtype=np.uint8)
            return [scene.add_point_cloud(f'{name}/points', shape.points.astype(np.float32), colors,
                                          point_size=max(sx, 1e-3), precision='float32', point_shading='flat',
                                          point_shape='circle' if shape.kind == 'sphere_list' else 'square')]
        if shape.kind == 'text':
            return [scene.add_label(f'{name}/text', shape.text, font_size_mode='scene',
                                    font_scene_height=max(sz, 0.01), anchor='center-center')]
        if shape.kind == 'triangle_list':
            count = len(shape.points) // 3 * 3
            if not count:
                return []
            faces = np.arange(count, dtype=np.uint32).reshape(-1, 3)
            return [scene.add_mesh_simple(f'{name}/triangles', shape.points[:count].astype(np.float32), faces,
                                          color=rgb, opacity=opacity, side='double', scale=(sx, sy, sz))]
        if shape.kind == 'mesh':
            return [self._mesh(f'{name}/mesh', str(marker.mesh_resource), (sx, sy, sz), rgb)]
        raise ValueError(f'marker type {shape.kind} is not supported')

    def _mesh(self, name: str, resource: str, scale: tuple[float, float, float], rgb: tuple[int, int, int]) -> Any:
        from zros.view.scene.meshes import load_mesh
        mesh = load_mesh(resource)
        return self.ctx.scene.add_mesh_simple(name, mesh.vertices.astype(np.float32), mesh.faces.astype(np.uint32),
                                              color=rgb, scale=scale)

    def _remove(self, key: tuple[str, int]) -> None:
        entry = self.markers.pop(key, None)
        self.problems.pop(key, None)
        if entry is not None:
            entry.node.remove()

    def redraw(self) -> None:
        for entry in self.markers.values():
            try:
                self._place(entry, 0)
            except FrameError:
                entry.node.visible = False

    def config(self) -> dict[str, Any]:
        return {**super().config(), 'class': 'MarkerArray' if self.msg_type.endswith('MarkerArray') else 'Marker'}

