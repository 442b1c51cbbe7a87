"""LaserScan and PointCloud2 as points placed with TF at the message's stamp; Image in the page."""
from __future__ import annotations

from typing import Any

import numpy as np

from zros.view.scene.convert import pointcloud2_points, scan_points
from zros.view.scene.displays.base import Display
from zros.view.scene.geometry import Transform

__all__ = ['LaserScanDisplay', 'PointCloud2Display', 'ImageDisplay', 'height_colors']


def height_colors(z: np.ndarray) -> np.ndarray:
    """(N, 3) uint8 rainbow colours of heights, blue low to red high (RViz's AxisColor on z)."""
    if z.size == 0:
        return np.zeros((0, 3), dtype=np.uint8)
    low, high = float(z.min()), float(z.max())
    t = (z - low) / (high - low) if high > low else np.zeros_like(z)
    ramp = 4.0 * t[:, None] - np.array([3.0, 2.0, 1.0])      # the "jet" ramps of red, green, blue
    rgb = np.clip(1.5 - np.abs(ramp), 0.0, 1.0)
    return (rgb * 255).astype(np.uint8)


class _PointsDisplay(Display):
    """A point cloud node under the display's root, whose pose is TF at the stamp."""

    defaults = {'color': (255, 0, 0), 'size': 0.04}

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self.cloud: Any = None
        self.count = 0

    def show(self, points: np.ndarray, colors: Any, pose: Transform) -> None:
        self.set_root_pose(pose)
        points = np.ascontiguousarray(points, dtype=np.float32)
        if self.cloud is None:
            self.cloud = self.ctx.scene.add_point_cloud(
                f'{self.root.name}/points', points, colors, point_size=float(self.options['size']),
                point_shape='circle', precision='float32', point_shading='flat')
        else:
            self.cloud.points = points
            self.cloud.colors = colors
            self.cloud.point_size = float(self.options['size'])
        self.count = len(points)


class LaserScanDisplay(_PointsDisplay):
    """RViz's LaserScan display: one point per valid beam, flat colour."""

    kind = 'LaserScan'
    msg_types = ('sensor_msgs/msg/LaserScan',)
    max_rate = 30.0

    def draw(self, msg: Any, pose: Transform) -> None:
        points = scan_points(msg.ranges, msg.angle_min, msg.angle_increment, msg.range_min, msg.range_max)
        self.show(points, np.asarray(self.options['color'], dtype=np.uint8), pose)

    def describe(self, msg: Any) -> str:
        return f'{self.count} of {len(msg.ranges)} beams in [{msg.header.frame_id}]'


class PointCloud2Display(_PointsDisplay):
    """RViz's PointCloud2 display: the cloud's rgb field if it has one, else coloured by height."""

    kind = 'PointCloud2'
    msg_types = ('sensor_msgs/msg/PointCloud2',)
    max_rate = 15.0
    defaults = {'color': None, 'size': 0.03}

    def draw(self, msg: Any, pose: Transform) -> None:
        points, colors = pointcloud2_points(msg)
        if self.options.get('color') is not None:
            colors = np.asarray(self.options['color'], dtype=np.uint8)
        elif colors is None:
            colors = height_colors(points[:, 2])
        self.show(points, colors, pose)

    def describe(self, msg: Any) -> str:
        return f'{self.count} points in [{msg.header.frame_id}]'


class ImageDisplay(Display):
    """RViz's Image display: the picture in the page's Images tab (not in the 3D scene)."""

    kind = 'Image'
    msg_types = ('sensor_msgs/msg/Image',)
    max_rate = 10.0
    placed_at_stamp = False

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self.widget: Any = None
        self.container: Any = None       # the view sets this to its Images tab

    def place(self, frame: str, stamp_ns: int) -> Transform:
        from zros.view.scene.geometry import IDENTITY
        return IDENTITY                  # an image is not placed in the scene

    def draw(self, msg: Any, pose: Transform) -> None:
        from zros.view.image import UnsupportedEncoding, image_to_array
        try:
            pixels = image_to_array(msg)
        except UnsupportedEncoding as exc:
            raise ValueError(str(exc)) from None
        if pixels.ndim == 2:
            pixels = np.repeat(pixels[..., None], 3, axis=2)
        if self.widget is None:
            if self.container is not None:
                with self.container:
                    self.widget = self.ctx.gui.add_image(pixels, label=self.topic, format='jpeg', jpeg_quality=85)
            else:
                self.widget = self.ctx.gui.add_image(pixels, label=self.topic, format='jpeg', jpeg_quality=85)
        else:
            self.widget.image = pixels

    def describe(self, msg: Any) -> str:
        return f'{msg.width} x {msg.height} {msg.encoding}'

    def set_enabled(self, enabled: bool) -> None:
        super().set_enabled(enabled)
        if self.widget is not None:
            self.widget.visible = enabled

    def destroy(self) -> None:
        if self.widget is not None:
            self.widget.remove()
        super().destroy()
