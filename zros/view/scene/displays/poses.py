"""Poses: Odometry, Pose (PoseStamped), PoseArray and nav2's ParticleCloud, PoseWithCovariance
(arrow + 1-sigma ellipse) and Path."""
from __future__ import annotations

import math
from collections import deque
from typing import Any

import numpy as np

from zros.view.scene.convert import (
    covariance_ellipse, flat_arrow_mesh, path_points, polyline_segments, pose_arrows, poses_array,
)
from zros.view.scene.displays.base import Display
from zros.view.scene.geometry import IDENTITY, Transform, pose_transform, wxyz

__all__ = ['PoseDisplay', 'OdometryDisplay', 'PoseArrayDisplay', 'PoseWithCovarianceDisplay', 'PathDisplay']

POSE_RGB = (255, 25, 0)           # RViz's default pose colour
PATH_RGB = (25, 255, 0)


class FlatArrows:
    """Many poses as flat arrows in one instanced mesh (2000 particles are one draw call)."""

    def __init__(self, display: Display, name: str) -> None:
        self.display, self.name = display, name
        self.handle: Any = None
        self._shape: tuple[int, float, tuple] | None = None

    def show(self, positions: np.ndarray, rotations: np.ndarray) -> None:
        options = self.display.options
        length, color = float(options['length']), tuple(int(c) for c in options['color'])
        positions = np.ascontiguousarray(positions, dtype=np.float32) + np.float32([0.0, 0.0, 0.005])
        wxyzs = np.ascontiguousarray(wxyz(rotations), dtype=np.float32)
        shape = (len(positions), length, color)
        if self.handle is not None and shape == self._shape:
            self.handle.batched_positions = positions
            self.handle.batched_wxyzs = wxyzs
            return
        if self.handle is not None:
            self.handle.remove()
        vertices, faces = flat_arrow_mesh(length)
        self.handle = self.display.ctx.scene.add_batched_meshes_simple(
            f'{self.display.root.name}/{self.name}', vertices, faces, wxyzs, positions, batched_colors=color,
            lod='off', side='double', flat_shading=True, cast_shadow=False, receive_shadow=False)
        self._shape = shape


class _ArrowDisplay(Display):
    """One solid arrow per message (RViz's "Arrow" shape)."""

    defaults = {'color': POSE_RGB, 'length': 0.5}

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self.arrow: Any = None

    def show_arrow(self, pose: Any, frame_pose: Transform) -> None:
        self.set_root_pose(frame_pose)
        local = pose_transform(pose)
        length = float(self.options['length'])
        points = pose_arrows(local.translation[None], local.rotation[None], length)
        if self.arrow is None:
            self.arrow = self.ctx.scene.add_arrows(
                f'{self.root.name}/arrow', points, np.asarray(self.options['color'], dtype=np.uint8),
                shaft_radius=length * 0.05, head_radius=length * 0.12, head_length=length * 0.3)
        else:
            self.arrow.points = points
            self.arrow.colors = np.asarray(self.options['color'], dtype=np.uint8)


class PoseDisplay(_ArrowDisplay):
    """RViz's Pose display (geometry_msgs/PoseStamped)."""

    kind = 'Pose'
    msg_types = ('geometry_msgs/msg/PoseStamped',)

    def qos(self) -> Any:
        return 10

    def draw(self, msg: Any, pose: Transform) -> None:
        self.show_arrow(msg.pose, pose)

    def describe(self, msg: Any) -> str:
        p = msg.pose.position
        return f'({p.x:.2f}, {p.y:.2f}) in [{msg.header.frame_id}]'

    def expects_stream(self) -> bool:
        return False


class PoseWithCovarianceDisplay(_ArrowDisplay):
    """RViz's PoseWithCovariance display: the arrow and the 1-sigma position ellipse."""

    kind = 'PoseWithCovariance'
    msg_types = ('geometry_msgs/msg/PoseWithCovarianceStamped',)
    defaults = {'color': POSE_RGB, 'length': 0.5, 'covariance_color': (204, 51, 204)}

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self.ellipse: Any = None
        self.disc: Any = None

    def qos(self) -> Any:
        return 5                  # volatile, as RViz: matches latched (AMCL) and plain (the tool) publishers

    def draw(self, msg: Any, pose: Transform) -> None:
        self.show_arrow(msg.pose.pose, pose)
        outline = covariance_ellipse(msg.pose.covariance) + pose_transform(msg.pose.pose).translation
        outline[:, 2] += 0.01
        segments = polyline_segments(outline, closed=True)
        color = np.asarray(self.options['covariance_color'], dtype=np.uint8)
        faces = np.array([[0, i, i + 1] for i in range(1, len(outline) - 1)], dtype=np.uint32)
        if self.ellipse is None:
            self.ellipse = self.ctx.scene.add_line_segments(f'{self.root.name}/ellipse', segments, color,
                                                            thickness=2.0, thickness_units='screen')
            self.disc = self.ctx.scene.add_mesh_simple(f'{self.root.name}/disc', outline.astype(np.float32), faces,
                                                       color=tuple(int(c) for c in color), opacity=0.3,
                                                       side='double', cast_shadow=False, receive_shadow=False)
        else:
            self.ellipse.points = segments
            self.disc.vertices = outline.astype(np.float32)

    def describe(self, msg: Any) -> str:
        cov = np.asarray(msg.pose.covariance, dtype=np.float64).reshape(6, 6)
        p = msg.pose.pose.position
        return (f'({p.x:.2f}, {p.y:.2f}) in [{msg.header.frame_id}], sigma x {math.sqrt(max(cov[0, 0], 0)):.2f} m, '
                f'y {math.sqrt(max(cov[1, 1], 0)):.2f} m, yaw {math.degrees(math.sqrt(max(cov[5, 5], 0))):.1f} deg')

    def expects_stream(self) -> bool:
        return False


class OdometryDisplay(_ArrowDisplay):
    """RViz's Odometry display: the last `keep` poses as arrows, a new one each time the robot
    moved `position_tolerance` [m] or turned `angle_tolerance` [rad]. Kept in the fixed frame."""

    kind = 'Odometry'
    msg_types = ('nav_msgs/msg/Odometry',)
    defaults = {'color': POSE_RGB, 'length': 0.3, 'keep': 100, 'position_tolerance': 0.1, 'angle_tolerance': 0.1}

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self.history: deque[Transform] = deque(maxlen=int(self.options['keep']))
        self.arrows = FlatArrows(self, 'arrows')

    def draw(self, msg: Any, pose: Transform) -> None:
        current = pose @ pose_transform(msg.pose.pose)
        if self.history:
            last = self.history[-1]
            moved = float(np.linalg.norm(current.translation - last.translation))
            turned = abs(math.remainder(current.yaw - last.yaw, 2 * math.pi))
            if moved < float(self.options['position_tolerance']) and turned < float(self.options['angle_tolerance']):
                return
        self.history.append(current)
        self.set_root_pose(IDENTITY)
        self.arrows.show(np.array([t.translation for t in self.history]), np.array([t.rotation for t in self.history]))

    def describe(self, msg: Any) -> str:
        p = msg.pose.pose.position
        return f'({p.x:.2f}, {p.y:.2f}) in [{msg.header.frame_id}], {len(self.history)} arrows kept'


class PoseArrayDisplay(Display):
    """RViz's PoseArray display (flat arrows); also nav2_msgs/ParticleCloud, AMCL's particles."""

    kind = 'PoseArray'
    msg_types = ('geometry_msgs/msg/PoseArray', 'nav2_msgs/msg/ParticleCloud')
    max_rate = 10.0
    defaults = {'color': POSE_RGB, 'length': 0.3}

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self.arrows = FlatArrows(self, 'arrows')
        self.count = 0

    def draw(self, msg: Any, pose: Transform) -> None:
        poses = msg.poses if hasattr(msg, 'poses') else [particle.pose for particle in msg.particles]
        positions, rotations = poses_array(poses)
        self.set_root_pose(pose)
        self.arrows.show(positions, rotations)
        self.count = len(positions)

    def describe(self, msg: Any) -> str:
        return f'{self.count} poses in [{msg.header.frame_id}]'


class PathDisplay(Display):
    """RViz's Path display: the poses joined by a line."""

    kind = 'Path'
    msg_types = ('nav_msgs/msg/Path',)
    max_rate = 10.0
    defaults = {'color': PATH_RGB, 'width': 3.0}

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self.lines: Any = None
        self.count = 0

    def qos(self) -> Any:
        return 10

    def draw(self, msg: Any, pose: Transform) -> None:
        points = path_points(msg.poses)
        points[:, 2] += 0.01
        segments = polyline_segments(points)
        self.set_root_pose(pose)
        color = np.asarray(self.options['color'], dtype=np.uint8)
        if self.lines is not None:
            self.lines.remove()             # the segment count changes with every plan
        self.lines = self.ctx.scene.add_line_segments(f'{self.root.name}/line', segments if len(segments) else
                                                      np.zeros((1, 2, 3), dtype=np.float32), color,
                                                      thickness=float(self.options['width']), thickness_units='screen')
        self.count = len(points)

    def describe(self, msg: Any) -> str:
        return f'{self.count} poses in [{msg.header.frame_id}]'

    def expects_stream(self) -> bool:
        return False
