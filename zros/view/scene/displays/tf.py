"""TF: every frame TF knows, as axes with its name, and a line to its parent (RViz's TF display)."""
from __future__ import annotations

from typing import Any

import numpy as np

from zros.view.scene.displays.base import ERROR, OK, WARN, Display, slug
from zros.view.scene.frames import stack_poses
from zros.view.scene.geometry import Transform, wxyz

__all__ = ['TFDisplay']

_TREE_PERIOD = 1.0          # [s] between re-reads of the frame list


class TFDisplay(Display):
    """Not a subscription of its own: it draws what the view's TF buffer holds, 30 times a second."""

    kind = 'TF'
    msg_types = ()
    max_rate = 30.0
    defaults = {'show_names': True, 'show_axes': True, 'show_arrows': True, 'marker_scale': 0.3}

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self.tree: dict[str, str] = {}
        self._tree_at = -_TREE_PERIOD
        self._last = 0.0
        self.axes: Any = None
        self.links: Any = None
        self.labels: dict[str, Any] = {}
        self.placed: dict[str, Transform] = {}

    def subscribe(self) -> None:
        pass

    def tick(self, now: float) -> None:
        if not self.enabled or now - self._last < 1.0 / self.max_rate:
            return
        self._last = now
        frames = self.ctx.frames
        if frames is None:
            self._set_status(ERROR, 'TF is not available')
            return
        if now - self._tree_at >= _TREE_PERIOD:
            self.tree = frames.tree()
            self._tree_at = now
        names = sorted(set(self.tree) | set(self.tree.values()))
        if not names:
            self._set_status(WARN, 'no transforms received on /tf or /tf_static')
            return
        placed = frames.place(self.ctx.fixed_frame, names)
        self.draw_frames(placed)
        missing = len(names) - len(placed)
        if not placed:
            self._set_status(ERROR, f'fixed frame [{self.ctx.fixed_frame}] is not connected to the '
                                    f'{len(names)} frames TF knows')
        elif missing:
            self._set_status(WARN, f'{len(placed)} frames, {missing} not connected to [{self.ctx.fixed_frame}]')
        else:
            self._set_status(OK, f'{len(placed)} frames')

    def draw_frames(self, placed: dict[str, Transform]) -> None:
        scale = float(self.options['marker_scale'])
        positions, rotations = stack_poses(placed)
        if self.axes is not None and len(self.placed) != len(placed):
            self.axes.remove()
            self.axes = None
        if self.options['show_axes'] and len(placed):
            if self.axes is None:
                self.axes = self.ctx.scene.add_batched_axes(
                    f'{self.root.name}/axes', wxyz(rotations), positions, axes_length=scale,
                    axes_radius=scale * 0.04)
            else:
                self.axes.batched_positions = positions
                self.axes.batched_wxyzs = wxyz(rotations)
        for name in set(self.labels) - set(placed):
            self.labels.pop(name).remove()
        if self.options['show_names']:
            for name, pose in placed.items():
                label = self.labels.get(name)
                if label is None:
                    self.labels[name] = self.ctx.scene.add_label(
                        f'{self.root.name}/names/{slug(name)}', name, position=pose.translation,
                        font_screen_scale=0.8, anchor='bottom-left')
                else:
                    label.position = pose.translation
        links = [(placed[child].translation, placed[parent].translation) for child, parent in self.tree.items()
                 if child in placed and parent in placed]
        segments = np.asarray(links, dtype=np.float32).reshape(-1, 2, 3)
        if self.options['show_arrows'] and len(segments):
            if self.links is not None and len(self.links.points) != len(segments):
                self.links.remove()
                self.links = None
            if self.links is None:
                self.links = self.ctx.scene.add_line_segments(f'{self.root.name}/links', segments, (230, 200, 40),
                                                              thickness=1.5, thickness_units='screen')
            else:
                self.links.points = segments
        self.placed = placed

    def set_option(self, name: str, value: Any) -> None:
        self.options[name] = value
        for label in self.labels.values():
            label.remove()
        self.labels.clear()
        for handle in (self.axes, self.links):
            if handle is not None:
                handle.remove()
        self.axes = self.links = None
        self.placed = {}

