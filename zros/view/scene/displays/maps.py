"""Map: nav_msgs/OccupancyGrid as a textured plane (maps and costmaps), re-sent only when it changed.

As RViz's Map display it also subscribes to `<topic>_updates` (map_msgs/OccupancyGridUpdate),
which Nav2's costmaps publish between whole grids: each update is pasted into the last grid, so a
costmap that sends only what changed (`always_send_full_costmap: false`, Nav2's default) is
shown as it is, not as it was at its last whole grid.
"""
from __future__ import annotations

import copy
import zlib
from typing import Any

import numpy as np

from zros.grid_update import apply_update
from zros.view.scene.convert import MAP_SCHEMES, grid_placement, known_window, occupancy_rgba
from zros.view.scene.displays.base import Display
from zros.view.scene.frames import FrameError
from zros.view.scene.geometry import Transform, wxyz

__all__ = ['MapDisplay']

_Z = {'map': -0.004, 'raw': -0.004, 'costmap': 0.002}   # [m] costmaps over maps, both under scans
_REPLACE_PERIOD = 0.1                                     # [s] follow TF this often between maps
_MARGIN = 20                                              # [cells] of unknown kept round the known part


class MapDisplay(Display):
    """RViz's Map display. Latched topic (reliable, transient local); the texture is rebuilt and
    sent only when the grid or the colour options change, while its pose follows TF."""

    kind = 'Map'
    msg_types = ('nav_msgs/msg/OccupancyGrid',)
    max_rate = 5.0
    placed_at_stamp = False
    defaults = {'color_scheme': 'map', 'alpha': 0.7, 'crop_unknown': True}

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self.image: Any = None
        self._key: tuple | None = None
        self._window: tuple[int, int, int, int] | None = None
        self._frame = ''
        self._replaced_at = 0.0
        self.uploads = 0               # textures sent to the browser (the benchmark reads it)
        self._grid: Any = None         # the last whole grid, with the updates since pasted in
        self._updates: Any = None      # the subscription to `<topic>_updates`

    def qos(self) -> Any:
        from zros.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
        return QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                          durability=DurabilityPolicy.TRANSIENT_LOCAL)

    def subscribe(self) -> None:
        super().subscribe()
        if self._subscription is None:
            return
        from zros.typesupport import get_message
        self._updates = self.ctx.node.create_subscription(
            get_message('map_msgs/msg/OccupancyGridUpdate'), f'{self.topic}_updates', self.on_update, self.qos())

    def unsubscribe(self) -> None:
        super().unsubscribe()
        self.destroy_subscription(self._updates)
        self._updates = None

    def on_message(self, msg: Any) -> None:
        with self._lock:
            self._grid = msg
        super().on_message(msg)

    def on_update(self, update: Any) -> None:
        """Paste an update into the last grid (node's executor thread) and show the result as
        the newest message. An update before any grid, or one that does not fit it (cut from a
        grid of another size), is dropped, as RViz does: the next whole grid puts things right."""
        with self._lock:
            grid = self._grid
        if grid is None:
            return
        info = grid.info
        data = np.array(grid.data, np.int8).reshape(int(info.height), int(info.width))   # a copy: draw may read the old
        try:
            apply_update(data, int(update.x), int(update.y), int(update.width), int(update.height), update.data)
        except ValueError:
            return
        patched = copy.copy(grid)
        patched.data = data.ravel()
        self.on_message(patched)

    def draw(self, msg: Any, pose: Transform) -> None:
        info = msg.info
        scheme = str(self.options['color_scheme'])
        if scheme not in MAP_SCHEMES:
            raise ValueError(f"unknown colour scheme '{scheme}'")
        data = np.asarray(msg.data)
        origin = info.origin
        key = (int(info.width), int(info.height), float(info.resolution), origin.position.x, origin.position.y,
               origin.position.z, origin.orientation.z, origin.orientation.w, scheme,
               float(self.options['alpha']), zlib.crc32(data.tobytes()))
        self._frame = msg.header.frame_id
        self.set_root_pose(pose)
        if key == self._key:
            return
        if info.width == 0 or info.height == 0:
            raise ValueError('the map is empty (0 cells)')
        rgba = occupancy_rgba(data, int(info.width), int(info.height), scheme, float(self.options['alpha']))
        window = None
        if self.options.get('crop_unknown'):       # only the known part and a margin: far less to draw
            window = known_window(data.reshape(int(info.height), int(info.width)), _MARGIN)
            if window is not None:
                rgba = np.ascontiguousarray(rgba[window[0]:window[1], window[2]:window[3]])
        centre, width_m, height_m = grid_placement(info, window)
        position = centre.translation + np.array([0.0, 0.0, _Z[scheme]])
        if self.image is None or self._key is None or self._key[:3] != key[:3] or window != self._window:
            if self.image is not None:
                self.image.remove()
            self.image = self.ctx.scene.add_image(f'{self.root.name}/grid', rgba, width_m, height_m, format='png',
                                                  position=position, wxyz=wxyz(centre.rotation),
                                                  cast_shadow=False, receive_shadow=False)
        else:
            self.image.image = rgba                       # same size: update the texture in place
            self.image.position = position
            self.image.wxyz = wxyz(centre.rotation)
        self._key, self._window = key, window
        self.uploads += 1

    def refresh(self, now: float) -> None:
        if not self._frame or now - self._replaced_at < _REPLACE_PERIOD:
            return
        self._replaced_at = now
        try:
            self.set_root_pose(self.place(self._frame, 0))
        except FrameError as exc:
            self._set_status('error', str(exc))

    def set_option(self, name: str, value: Any) -> None:
        super().set_option(name, value)
        self._key = None

    def describe(self, msg: Any) -> str:
        info = msg.info
        return f'{info.width} x {info.height} cells of {info.resolution:g} m in [{msg.header.frame_id}]'

    def expects_stream(self) -> bool:
        return False
