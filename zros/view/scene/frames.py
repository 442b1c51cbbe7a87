"""Where the view asks TF: one small seam over zros.tf2_ros's Buffer and TransformListener.

Every display places its data through `Frames.lookup(fixed, frame, stamp_ns)`; nothing else in
the view knows about TF. A failed lookup becomes a `FrameError` whose text is what the page
shows next to the display (RViz's "No transform from [base_scan] to [map]"), and `pending`
says whether waiting may help (the transform for the message's stamp has not arrived yet, as
RViz's message filter waits).
"""
from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from zros.view.scene.geometry import IDENTITY, Transform, transform_of_msg

if TYPE_CHECKING:
    from zros.node import Node

__all__ = ['Frames', 'FrameError']


class FrameError(Exception):
    """A frame cannot be placed in the fixed frame; `pending` if a later try may succeed."""

    def __init__(self, message: str, *, pending: bool = False) -> None:
        super().__init__(message)
        self.pending = pending


class Frames:
    """TF for the view: a Buffer filled by a TransformListener on `node`.

    Thread contract: the node's executor fills the buffer; the view's render thread calls
    `lookup` and `tree`.
    """

    def __init__(self, node: 'Node') -> None:
        from zros.tf2_ros import Buffer, TransformListener
        self._buffer = Buffer()          # no tf2_frames service: several views may run (RViz serves none)
        self._listener = TransformListener(self._buffer, node)

    def lookup(self, target: str, source: str, stamp_ns: int = 0) -> Transform:
        """The transform taking points in `source` to `target` at `stamp_ns` (0: the latest).

        Raises:
            FrameError: no such frame, not connected, or not (yet) known at that time.
        """
        from zros.tf2_ros import ExtrapolationException, TransformException
        from zros.time import Time
        source = source.lstrip('/')
        target = target.lstrip('/')
        if not source:
            raise FrameError('the message has an empty frame_id')
        if source == target:
            return IDENTITY
        try:
            stamped = self._buffer.lookup_transform(target, source, Time(nanoseconds=max(0, int(stamp_ns))))
        except ExtrapolationException as exc:
            raise FrameError(f'No transform from [{source}] to [{target}] at that time: {exc}',
                             pending=True) from None
        except TransformException as exc:
            known = self.tree()
            if source not in known and source not in known.values():
                raise FrameError(f'No transform from [{source}] to [{target}]: frame [{source}] does not exist',
                                 pending=True) from None
            if target not in known and target not in known.values():
                raise FrameError(f'No transform from [{source}] to [{target}]: fixed frame [{target}] does not exist',
                                 pending=True) from None
            raise FrameError(f'No transform from [{source}] to [{target}]: {exc}', pending=True) from None
        return transform_of_msg(stamped.transform)

    def tree(self) -> dict[str, str]:
        """Every known frame that has a parent, as {child: parent}."""
        return {child: info['parent'] for child, info in self._buffer.frames().items()}

    def place(self, target: str, frames: list[str]) -> dict[str, Transform]:
        """The latest pose in `target` of every frame of `frames` that can be placed."""
        placed: dict[str, Transform] = {}
        for frame in frames:
            try:
                placed[frame] = self.lookup(target, frame)
            except FrameError:
                continue
        return placed


def stack_poses(poses: dict[str, Transform]) -> tuple[np.ndarray, np.ndarray]:
    """Positions (N, 3) and xyzw rotations (N, 4) of a dict of transforms, in its order."""
    if not poses:
        return np.zeros((0, 3)), np.zeros((0, 4))
    return (np.array([t.translation for t in poses.values()]), np.array([t.rotation for t in poses.values()]))
