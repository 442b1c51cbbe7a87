"""What every display shares: its subscription, the latest message, throttling, TF placement and
the status line the page shows.

Thread contract: the node's executor calls `on_message` (which only stores the message and
wakes the render thread); the view's render thread calls `tick`, which converts the newest
message when the display's rate allows, places it with TF, and updates the scene. So a burst
of messages costs one conversion, and a slow browser never slows the node.
"""
from __future__ import annotations

import threading
import time
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Callable, ClassVar

import numpy as np

from zros.view.scene.frames import FrameError
from zros.view.scene.geometry import IDENTITY, Transform, wxyz

if TYPE_CHECKING:
    import viser

    from zros.node import Node
    from zros.view.scene.frames import Frames

__all__ = ['Display', 'DisplayContext', 'Status', 'OK', 'WARN', 'ERROR', 'DISABLED', 'SILENT_AFTER', 'WAITING', 'stamp_ns',
           'slug']

OK, WARN, ERROR, DISABLED = 'ok', 'warn', 'error', 'disabled'
SILENT_AFTER = 5.0          # [s] without a message (and no publisher) before the display says so
WAITING = 'waiting for the first message'   # a display's status until it has drawn or knows why not
PENDING_FOR = 1.0           # [s] a message waits for its transform before the failure is shown


@dataclass(frozen=True)
class Status:
    level: str
    text: str


@dataclass
class DisplayContext:
    """What the view lends its displays: the scene, TF, the fixed frame and the node."""
    scene: 'viser.SceneApi'
    gui: 'viser.GuiApi'
    node: 'Node'
    frames: 'Frames | None'
    fixed_frame: str
    wake: threading.Event
    publishers: Callable[[str], int] = lambda topic: 0


class Display:
    """One entry of the Displays list: a topic drawn in the scene.

    Subclasses set `kind` (RViz's class name), `msg_types`, `max_rate` [Hz] and implement
    `draw(msg, pose)`; `pose` is the transform from the message's frame to the fixed frame at
    the message's stamp. `defaults` lists the options (name -> default) that the page shows
    and the view file saves.
    """

    kind: ClassVar[str] = ''
    msg_types: ClassVar[tuple[str, ...]] = ()
    max_rate: ClassVar[float] = 30.0
    defaults: ClassVar[dict[str, Any]] = {}
    placed_at_stamp: ClassVar[bool] = True     # False: place with the latest transform (static data)

    def __init__(self, ctx: DisplayContext, name: str, topic: str = '', options: dict[str, Any] | None = None,
                 *, msg_type: str | None = None) -> None:
        self.ctx = ctx
        self.name = name
        self.topic = topic
        self.msg_type = msg_type or (self.msg_types[0] if self.msg_types else '')
        self.options = {**self.defaults, **(options or {})}
        self.enabled = True
        self.root = ctx.scene.add_frame(f'/displays/{slug(name)}', show_axes=False)
        self._subscription: Any = None
        self._lock = threading.Lock()
        self._latest: Any = None
        self._latest_at = 0.0
        self._drawn: Any = None
        self._pending_since = 0.0
        self._drawn_at = 0.0
        self._last_message_at = 0.0
        self._created_at = time.monotonic()
        self.received = 0
        self.status = Status(WARN, WAITING if topic else 'ok')
        self.on_status: Callable[['Display'], None] | None = None

    # -- subscription (node's executor thread) ---------------------------------------------
    def qos(self) -> Any:
        from zros.qos import qos_profile_sensor_data
        return qos_profile_sensor_data

    def subscribe(self) -> None:
        """(Re)subscribe to `self.topic` with the display's message type."""
        self.unsubscribe()
        if not self.topic or not self.enabled:
            return
        from zros.typesupport import get_message
        msg_class = get_message(self.msg_type)
        self._subscription = self.ctx.node.create_subscription(msg_class, self.topic, self.on_message, self.qos())

    def unsubscribe(self) -> None:
        self.destroy_subscription(self._subscription)
        self._subscription = None

    def destroy_subscription(self, subscription: Any) -> None:
        """Destroy one of the display's subscriptions (None: nothing to do)."""
        if subscription is not None:
            try:
                self.ctx.node.destroy_subscription(subscription)
            except Exception:  # noqa: BLE001 - the node may be shutting down
                pass

    def on_message(self, msg: Any) -> None:
        with self._lock:
            self._latest = msg
            self._latest_at = time.monotonic()
            self.received += 1
        self.ctx.wake.set()

    # -- rendering (render thread) ---------------------------------------------------------
    def tick(self, now: float) -> None:
        """Draw the newest message if the rate allows; keep the status line current."""
        if not self.enabled:
            return
        if now - self._drawn_at < 1.0 / self.max_rate:
            return
        with self._lock:
            msg, received_at = self._latest, self._latest_at
        if msg is None:
            self._check_silence(now)
            self.refresh(now)
            return
        header = getattr(msg, 'header', None)
        frame = header.frame_id if header is not None else self.ctx.fixed_frame
        stamp = stamp_ns(header) if (header is not None and self.placed_at_stamp) else 0
        try:
            pose = self.place(frame, stamp)
        except FrameError as exc:
            self._pending_since = self._pending_since or now
            if exc.pending and now - self._pending_since < PENDING_FOR:
                return                                    # the transform for the stamp may still come
            pose = self._latest_pose(frame, stamp, exc)
            if pose is None:
                with self._lock:
                    if self._latest is msg:
                        self._latest = None               # drop it; the next message tries again
                return
        with self._lock:
            if self._latest is msg:
                self._latest = None
        self._pending_since = 0.0
        self._drawn_at = now
        self._drawn = msg
        self._last_message_at = received_at
        try:
            self.draw(msg, pose)
        except (ValueError, KeyError, IndexError) as exc:
            self._set_status(ERROR, f'cannot show this message: {exc}')
            return
        self._set_status(OK, self.describe(msg))

    def place(self, frame: str, stamp_ns: int) -> Transform:
        """The pose of `frame` in the fixed frame at `stamp_ns` (TF; identity if it is the fixed frame).

        Raises:
            FrameError: TF cannot place it (yet).
        """
        if frame.lstrip('/') == self.ctx.fixed_frame.lstrip('/'):
            return IDENTITY
        if self.ctx.frames is None:
            raise FrameError(f'No transform from [{frame}] to [{self.ctx.fixed_frame}]: TF is not available')
        return self.ctx.frames.lookup(self.ctx.fixed_frame, frame, stamp_ns)

    def _latest_pose(self, frame: str, stamp_ns: int, error: FrameError) -> Transform | None:
        """After waiting for the stamp in vain, the latest transform (a clock mismatch between
        the publisher and TF should not blank the display); None, with the status set, if
        there is none either."""
        if stamp_ns and error.pending:
            try:
                return self.place(frame, 0)
            except FrameError as exc:
                error = exc
        self._set_status(ERROR, str(error))
        return None

    def set_root_pose(self, pose: Transform) -> None:
        self.root.position = np.asarray(pose.translation, dtype=np.float64)
        self.root.wxyz = wxyz(pose.rotation)

    def _check_silence(self, now: float) -> None:
        if not self.topic:
            return
        quiet_since = self._last_message_at or self._created_at
        if now - quiet_since < SILENT_AFTER:
            return
        count = self.ctx.publishers(self.topic)
        if count == 0:
            self._set_status(WARN, f'topic {self.topic} has no publisher')
        elif self._last_message_at == 0.0:
            self._set_status(WARN, f'no message received on {self.topic} for {now - quiet_since:.0f} s '
                                   f'({count} publisher{"s" if count != 1 else ""})')
        elif self.expects_stream():
            self._set_status(WARN, f'topic {self.topic} is silent: last message {now - quiet_since:.0f} s ago')

    def _set_status(self, level: str, text: str) -> None:
        status = Status(level, text)
        if status != self.status:
            self.status = status
            if self.on_status is not None:
                self.on_status(self)

    # -- what subclasses provide -----------------------------------------------------------
    def draw(self, msg: Any, pose: Transform) -> None:
        raise NotImplementedError

    def refresh(self, now: float) -> None:
        """Called on ticks without a new message (displays that follow TF move here)."""

    def describe(self, msg: Any) -> str:
        """The status text after a successful draw."""
        return 'ok'

    def expects_stream(self) -> bool:
        """True if silence after the first message is worth reporting (not for latched maps)."""
        return True

    def set_option(self, name: str, value: Any) -> None:
        """Change one option and redraw the last message with it."""
        self.options[name] = value
        self.redraw()

    def redraw(self) -> None:
        """Draw the last message again at the next tick (after an option or the fixed frame changed)."""
        with self._lock:
            if self._latest is None and self._drawn is not None:
                self._latest, self._latest_at = self._drawn, time.monotonic()
        self._drawn_at = 0.0
        self.ctx.wake.set()

    def set_enabled(self, enabled: bool) -> None:
        self.enabled = enabled
        self.root.visible = enabled
        if enabled:
            self.subscribe()
            self.status = Status(WARN, WAITING)
        else:
            self.unsubscribe()
            self._set_status(DISABLED, 'disabled')

    def destroy(self) -> None:
        self.unsubscribe()
        self.root.remove()

    def config(self) -> dict[str, Any]:
        """This display as a view-file entry."""
        return {'class': self.kind, 'name': self.name, 'topic': self.topic, 'type': self.msg_type,
                'enabled': self.enabled, **{k: v for k, v in self.options.items()}}


def stamp_ns(header: Any) -> int:
    """A std_msgs/Header's stamp in nanoseconds."""
    return int(header.stamp.sec) * 1_000_000_000 + int(header.stamp.nanosec)


def slug(name: str) -> str:
    """`name` made safe as one part of a viser scene path."""
    return ''.join(c if c.isalnum() or c in '-_' else '_' for c in name) or 'display'
