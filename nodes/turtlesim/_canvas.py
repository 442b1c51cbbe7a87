"""turtlesim's canvas: a 500 x 500 rgb8 picture of the background, the pen trails and the turtles.

ROS 2's turtlesim paints with Qt; this module paints the same picture into numpy arrays so that
it can be published as a sensor_msgs/Image and shown by any viewer. The trails live in their
own layer (colour plus a coverage mask) above a flat background, so a background change shows
at once and keeps the trails, as in current ROS 2.

Coordinates here are pixels: x to the right, y down, (0, 0) the top-left pixel's centre.
"""
from __future__ import annotations

import math
from typing import Iterable, NamedTuple

import numpy as np

__all__ = ['Canvas', 'Sprite', 'SHELL_COLORS']

# Shell colours of the turtle sprites; a spawned turtle gets one at random, as ROS picks one
# of its turtle images at random.
SHELL_COLORS: tuple[tuple[int, int, int], ...] = (
    (46, 139, 87), (34, 110, 60), (107, 142, 35), (0, 128, 128),
    (139, 90, 43), (85, 107, 47), (60, 120, 160), (150, 75, 120),
)
_SKIN = (150, 200, 110)
_OUTLINE = (20, 45, 20)


class Sprite(NamedTuple):
    """Where and how to draw one turtle: centre in pixels, heading in radians (CCW, +x = 0)."""
    px: float
    py: float
    theta: float
    shell: tuple[int, int, int]


class Canvas:
    """The background colour, the trail layer, and a renderer that adds the turtles.

    Not thread-safe: the node calls it under its world lock.
    """

    def __init__(self, size: int = 500, background: tuple[int, int, int] = (69, 86, 255)) -> None:
        self.size = size
        self.background = tuple(int(c) for c in background)
        self.trail = np.zeros((size, size, 3), dtype=np.uint8)
        self.mask = np.zeros((size, size), dtype=bool)
        ys, xs = np.mgrid[0:size, 0:size]
        self._xs = xs.astype(np.float32)
        self._ys = ys.astype(np.float32)

    def clear(self) -> None:
        """Remove every trail (the /clear service)."""
        self.mask[:] = False

    def line(self, p0: tuple[float, float], p1: tuple[float, float], color: tuple[int, int, int],
             width: int) -> None:
        """Draw a segment `width` pixels wide with round ends into the trail layer."""
        radius = max(0.5, width / 2.0)
        x0, y0 = p0
        x1, y1 = p1
        lo_x = max(0, int(math.floor(min(x0, x1) - radius)))
        hi_x = min(self.size - 1, int(math.ceil(max(x0, x1) + radius)))
        lo_y = max(0, int(math.floor(min(y0, y1) - radius)))
        hi_y = min(self.size - 1, int(math.ceil(max(y0, y1) + radius)))
        if lo_x > hi_x or lo_y > hi_y:
            return
        xs = self._xs[lo_y:hi_y + 1, lo_x:hi_x + 1]
        ys = self._ys[lo_y:hi_y + 1, lo_x:hi_x + 1]
        dx, dy = x1 - x0, y1 - y0
        length2 = dx * dx + dy * dy
        if length2 > 1e-12:
            t = np.clip(((xs - x0) * dx + (ys - y0) * dy) / length2, 0.0, 1.0)
        else:
            t = np.zeros_like(xs)
        dist2 = (xs - (x0 + t * dx)) ** 2 + (ys - (y0 + t * dy)) ** 2
        hit = dist2 <= radius * radius
        if not hit.any():
            return
        self.trail[lo_y:hi_y + 1, lo_x:hi_x + 1][hit] = color
        self.mask[lo_y:hi_y + 1, lo_x:hi_x + 1] |= hit

    def pixel(self, px: float, py: float) -> tuple[int, int, int]:
        """The colour under a point (trail if any, else background), as the colour sensor sees it."""
        ix = min(self.size - 1, max(0, int(round(px))))
        iy = min(self.size - 1, max(0, int(round(py))))
        if self.mask[iy, ix]:
            r, g, b = self.trail[iy, ix]
            return int(r), int(g), int(b)
        return self.background  # type: ignore[return-value]

    def render(self, sprites: Iterable[Sprite] = ()) -> np.ndarray:
        """A new (size, size, 3) uint8 frame: background, trails, then the turtles on top."""
        frame = np.empty((self.size, self.size, 3), dtype=np.uint8)
        frame[:] = self.background
        np.copyto(frame, self.trail, where=self.mask[..., None])
        for sprite in sprites:
            _draw_turtle(frame, sprite)
        return frame


# The turtle, in its own frame: u forward, v to its left, in pixels (the ROS images are 45 px).
# Each part is an ellipse (centre u, centre v, half-length along u, half-width along v, colour).
def _turtle_parts(shell: tuple[int, int, int]) -> list[tuple[float, float, float, float, tuple[int, int, int]]]:
    dark = tuple(max(0, int(c * 0.6)) for c in shell)
    return [
        (-15.0, 0.0, 4.0, 2.5, _SKIN),           # tail
        (8.0, 10.0, 4.0, 3.5, _SKIN),            # front legs
        (8.0, -10.0, 4.0, 3.5, _SKIN),
        (-8.0, 10.0, 4.0, 3.5, _SKIN),           # back legs
        (-8.0, -10.0, 4.0, 3.5, _SKIN),
        (14.0, 0.0, 6.0, 5.0, _SKIN),            # head
        (-1.0, 0.0, 14.0, 11.0, _OUTLINE),       # shell rim
        (-1.0, 0.0, 12.5, 9.5, dark),            # shell
        (-1.0, 0.0, 8.0, 5.5, shell),            # shell plate
        (17.0, 2.5, 1.2, 1.2, _OUTLINE),         # eyes
        (17.0, -2.5, 1.2, 1.2, _OUTLINE),
    ]


_HALF = 23  # the sprite fits a 47 x 47 patch at any heading


def _draw_turtle(frame: np.ndarray, sprite: Sprite) -> None:
    size = frame.shape[0]
    cx, cy = int(round(sprite.px)), int(round(sprite.py))
    lo_x, hi_x = max(0, cx - _HALF), min(size - 1, cx + _HALF)
    lo_y, hi_y = max(0, cy - _HALF), min(size - 1, cy + _HALF)
    if lo_x > hi_x or lo_y > hi_y:
        return
    ys, xs = np.mgrid[lo_y:hi_y + 1, lo_x:hi_x + 1].astype(np.float32)
    dx, dy = xs - sprite.px, ys - sprite.py
    cos_t, sin_t = math.cos(sprite.theta), math.sin(sprite.theta)
    # Screen y points down while the world's y points up, hence the signs.
    u = dx * cos_t - dy * sin_t
    v = -dx * sin_t - dy * cos_t
    patch = frame[lo_y:hi_y + 1, lo_x:hi_x + 1]
    for cu, cv, au, av, color in _turtle_parts(sprite.shell):
        inside = ((u - cu) / au) ** 2 + ((v - cv) / av) ** 2 <= 1.0
        patch[inside] = color
