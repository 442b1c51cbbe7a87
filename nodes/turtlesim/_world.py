"""turtlesim's world: turtles moved by pymunk, with ROS 2 turtlesim's rules and numbers.

Kept free of zros so that it can be tested (and reasoned about) as plain physics: the node
feeds it commands, calls `advance()` with the wall-clock time that passed, and turns the
events it returns into messages.

What matches ROS 2's turtlesim (turtle.cpp, turtle_frame.cpp):
- the world is (500 - 1) / 45 = 11.0889 m square (45 px per metre, the turtle images' height),
  y up, turtle1 starts in the middle facing +x;
- one update every 16 ms (62.5 Hz) with dt = 0.016 s; a velocity command holds for 1 s;
- teleports are queued and applied at the start of the next update, drawing a line if the pen
  is down; a turtle that would leave the world logs "Oh no! I hit the wall! (Clamping from
  [x=..., y=...])" with ROS's screen coordinates (y measured down from the top);
- rotate_absolute turns at 1 rad/s towards the goal and succeeds within 0.02 rad.

What pymunk does: each turtle is a dynamic body of infinite moment whose velocity is set to
the commanded one in every step (its velocity function), so the contact solver can take away
the part that pushes into a wall; the walls are four static segments just outside the world
so a turtle's centre stops on the border, like ROS's clamp (which still runs, to remove the
solver's last fraction of a millimetre). Turtles do not collide with each other, as in ROS.
Time advances in fixed 16 ms steps: real time is accumulated and stepped in whole slices, so
wall-clock jitter never changes the physics.
"""
from __future__ import annotations

import math
import random
from dataclasses import dataclass, field
from typing import Any, Callable, NamedTuple

import pymunk

from zros.rotations import wrap_angle

from nodes.turtlesim._canvas import SHELL_COLORS, Canvas, Sprite

__all__ = ['World', 'Turtle', 'Pen', 'Rotation', 'Event', 'TurtleError',
           'CANVAS_PX', 'METER_PX', 'WORLD_SIZE', 'DT', 'COMMAND_TIMEOUT', 'DEFAULT_BACKGROUND',
           'DEFAULT_PEN']

CANVAS_PX = 500
METER_PX = 45.0
WORLD_SIZE = (CANVAS_PX - 1) / METER_PX      # 11.0889 m
DT = 0.016                                   # ROS's QTimer interval, 16 ms
COMMAND_TIMEOUT = 1.0
ROTATE_SPEED = 1.0                           # rad/s, rotate_absolute
ROTATE_TOLERANCE = 0.02                      # rad
DEFAULT_BACKGROUND = (69, 86, 255)           # 0x45, 0x56, 0xff
DEFAULT_PEN = (179, 184, 255)                # 0xb3, 0xb8, 0xff
DEFAULT_PEN_WIDTH = 3
# Longest catch-up after a stall: beyond this many steps per call the rest of the time is
# dropped (the simulation slows down rather than spiralling).
MAX_STEPS_PER_ADVANCE = 10

_TURTLE_RADIUS = 0.1         # collision circle; the wall segments sit this far outside
# A turtle whose centre is this far past the border (a teleport or spawn outside, or a speed
# that would tunnel through a wall in one step) is put back on the border; pymunk's contact
# solver handles everything closer.
_SNAP_DISTANCE = 0.75 * _TURTLE_RADIUS
_WALL_CATEGORY = 0b01
_TURTLE_CATEGORY = 0b10


class TurtleError(ValueError):
    """A request the world refuses (unknown or duplicate turtle name)."""


@dataclass
class Pen:
    r: int = DEFAULT_PEN[0]
    g: int = DEFAULT_PEN[1]
    b: int = DEFAULT_PEN[2]
    width: int = DEFAULT_PEN_WIDTH
    on: bool = True

    @property
    def color(self) -> tuple[int, int, int]:
        return (self.r, self.g, self.b)


@dataclass
class Rotation:
    """A rotate_absolute goal being carried out. `token` is the caller's (the goal handle);
    `cancel_requested()` is polled every step."""
    target: float
    start: float
    token: Any
    cancel_requested: Callable[[], bool]
    delta: float = 0.0


class Event(NamedTuple):
    """Something a step produced for the node to publish.

    kind: 'pose' (data: x, y, theta, linear_velocity, angular_velocity), 'color' (r, g, b),
    'feedback' (the Rotation, remaining), 'succeeded' / 'canceled' (the Rotation), 'wall' (x, y in ROS's
    screen frame).
    """
    kind: str
    turtle: str
    data: Any


@dataclass
class Turtle:
    name: str
    body: pymunk.Body
    shape: pymunk.Circle
    shell: tuple[int, int, int]
    pen: Pen = field(default_factory=Pen)
    lin_x: float = 0.0
    lin_y: float = 0.0
    ang: float = 0.0
    last_command: float = 0.0
    teleports: list[tuple[str, float, float, float]] = field(default_factory=list)
    rotation: Rotation | None = None
    # The position turtlesim reports (and draws): the body's, clamped to the world as ROS does.
    x: float = 0.0
    y: float = 0.0

    @property
    def theta(self) -> float:
        return float(self.body.angle)

    def world_velocity(self) -> tuple[float, float]:
        """The commanded body-frame velocity, turned into the world frame."""
        c, s = math.cos(self.body.angle), math.sin(self.body.angle)
        return (c * self.lin_x - s * self.lin_y, s * self.lin_x + c * self.lin_y)

    def linear_speed(self) -> float:
        """Pose.linear_velocity: |v|, negative when driving backwards (see docs/turtlesim.md)."""
        speed = math.hypot(self.lin_x, self.lin_y)
        return -speed if self.lin_x < 0.0 else speed


class World:
    """Turtles, walls and the canvas. Not thread-safe: one caller at a time (the node's lock)."""

    def __init__(self, *, size: float = WORLD_SIZE, dt: float = DT,
                 background: tuple[int, int, int] = DEFAULT_BACKGROUND, rng: random.Random | None = None) -> None:
        self.width = self.height = float(size)
        self.dt = float(dt)
        self.time = 0.0
        self.turtles: dict[str, Turtle] = {}
        self.canvas = Canvas(CANVAS_PX, background)
        self._id_counter = 0
        self._accumulated = 0.0
        self._rng = rng or random.Random()
        self.space = pymunk.Space()
        self.space.gravity = (0.0, 0.0)
        # Metres, not pixels: pymunk's default slop (0.1) would let a turtle 10 cm into a wall;
        # and a stronger bias takes out two thirds of an overlap per 16 ms step.
        self.space.collision_slop = 0.0005
        self.space.collision_bias = 1e-30
        self._add_walls()

    def _add_walls(self) -> None:
        w, h, r = self.width, self.height, _TURTLE_RADIUS
        corners = [(-r, -r), (w + r, -r), (w + r, h + r), (-r, h + r)]
        wall_filter = pymunk.ShapeFilter(categories=_WALL_CATEGORY, mask=_TURTLE_CATEGORY)
        for a, b in zip(corners, corners[1:] + corners[:1]):
            wall = pymunk.Segment(self.space.static_body, a, b, 0.0)
            wall.friction = 0.0
            wall.elasticity = 0.0
            wall.filter = wall_filter
            self.space.add(wall)

    # -- turtles -----------------------------------------------------------------------------
    def has_turtle(self, name: str) -> bool:
        return name in self.turtles

    def next_name(self) -> str:
        """ROS's naming: turtle<N> with a counter that only /reset sets back."""
        while True:
            self._id_counter += 1
            name = f'turtle{self._id_counter}'
            if name not in self.turtles:
                return name

    def spawn(self, name: str, x: float, y: float, theta: float) -> Turtle:
        """Add a turtle (an empty name gets a generated one); TurtleError if the name is taken."""
        if not name:
            name = self.next_name()
        elif name in self.turtles:
            raise TurtleError(f'A turtle named [{name}] already exists')
        body = pymunk.Body(1.0, float('inf'))
        body.position = (float(x), float(y))
        body.angle = float(theta)
        shape = pymunk.Circle(body, _TURTLE_RADIUS)
        shape.friction = 0.0
        shape.elasticity = 0.0
        shape.filter = pymunk.ShapeFilter(categories=_TURTLE_CATEGORY, mask=_WALL_CATEGORY)
        turtle = Turtle(name, body, shape, self._rng.choice(SHELL_COLORS), last_command=self.time,
                        x=float(x), y=float(y))
        body.velocity_func = _velocity_control(turtle)
        self.space.add(body, shape)
        self.turtles[name] = turtle
        return turtle

    def kill(self, name: str) -> Turtle:
        turtle = self.turtles.pop(name, None)
        if turtle is None:
            raise TurtleError(f'Tried to kill turtle [{name}], which does not exist')
        self.space.remove(turtle.body, turtle.shape)
        return turtle

    def turtle(self, name: str) -> Turtle:
        try:
            return self.turtles[name]
        except KeyError:
            raise TurtleError(f'No turtle named [{name}]') from None

    def reset(self) -> list[Turtle]:
        """Remove every turtle, restart the name counter, clear the canvas; returns the removed."""
        removed = list(self.turtles.values())
        for turtle in removed:
            self.space.remove(turtle.body, turtle.shape)
        self.turtles.clear()
        self._id_counter = 0
        self.canvas.clear()
        return removed

    def center(self) -> tuple[float, float]:
        return (self.width / 2.0, self.height / 2.0)

    # -- commands (applied by the next step) ---------------------------------------------------
    def command(self, name: str, lin_x: float, lin_y: float, ang: float) -> Rotation | None:
        """A cmd_vel: holds for COMMAND_TIMEOUT s. Returns the rotation goal it interrupts, if any
        (ROS aborts it: "Velocity command received during rotation goal")."""
        turtle = self.turtle(name)
        turtle.lin_x, turtle.lin_y, turtle.ang = float(lin_x), float(lin_y), float(ang)
        turtle.last_command = self.time
        interrupted, turtle.rotation = turtle.rotation, None
        return interrupted

    def teleport_absolute(self, name: str, x: float, y: float, theta: float) -> None:
        self.turtle(name).teleports.append(('absolute', float(x), float(y), float(theta)))

    def teleport_relative(self, name: str, linear: float, angular: float) -> None:
        self.turtle(name).teleports.append(('relative', float(linear), 0.0, float(angular)))

    def set_pen(self, name: str, r: int, g: int, b: int, width: int, off: bool) -> None:
        """ROS's set_pen: `off` lifts the pen and keeps its colour; otherwise a new pen, whose
        width is `width` or Qt's default of 1 when `width` is 0."""
        turtle = self.turtle(name)
        turtle.pen.on = not off
        if off:
            return
        turtle.pen = Pen(int(r), int(g), int(b), int(width) if width else 1, True)

    def start_rotation(self, name: str, target: float, token: Any,
                       cancel_requested: Callable[[], bool]) -> Rotation | None:
        """Begin a rotate_absolute goal; returns the goal it preempts, if any."""
        turtle = self.turtle(name)
        previous = turtle.rotation
        turtle.rotation = Rotation(float(target), turtle.theta, token, cancel_requested)
        return previous

    # -- time -------------------------------------------------------------------------------
    def advance(self, elapsed: float) -> list[list[Event]]:
        """Account for `elapsed` seconds of real time: run as many whole steps as fit (at most
        MAX_STEPS_PER_ADVANCE) and keep the remainder for the next call. Returns each step's
        events."""
        self._accumulated += max(0.0, float(elapsed))
        steps = []
        while self._accumulated >= self.dt and len(steps) < MAX_STEPS_PER_ADVANCE:
            self._accumulated -= self.dt
            steps.append(self.step())
        if self._accumulated >= self.dt:
            self._accumulated = 0.0
        return steps

    def step(self) -> list[Event]:
        """One fixed update of every turtle (ROS's Turtle::update, with pymunk integrating)."""
        events: list[Event] = []
        before: dict[str, tuple[float, float]] = {}
        for turtle in self.turtles.values():
            self._apply_teleports(turtle)
            self._run_rotation(turtle, events)
            if self.time - turtle.last_command > COMMAND_TIMEOUT:
                turtle.lin_x = turtle.lin_y = turtle.ang = 0.0
            before[turtle.name] = (turtle.x, turtle.y)
            # Free of contacts, start the step at the commanded velocity (no step of lag); in
            # contact, the solver's velocity from the last step stands, so it never digs in.
            if not _touching(turtle.body):
                turtle.body.velocity = turtle.world_velocity()
            turtle.body.angular_velocity = turtle.ang
        self.space.step(self.dt)
        self.time += self.dt
        for turtle in self.turtles.values():
            old_x, old_y = before[turtle.name]
            self._settle(turtle, old_x, old_y, events)
            if (turtle.x, turtle.y) != (old_x, old_y) and turtle.pen.on:
                self.canvas.line(self.to_pixels(old_x, old_y), self.to_pixels(turtle.x, turtle.y),
                                 turtle.pen.color, turtle.pen.width)
            events.append(Event('pose', turtle.name, (turtle.x, turtle.y, turtle.theta,
                                                      turtle.linear_speed(), turtle.ang)))
            events.append(Event('color', turtle.name, self.canvas.pixel(*self.to_pixels(turtle.x, turtle.y))))
        return events

    def _apply_teleports(self, turtle: Turtle) -> None:
        for kind, a, b, theta in turtle.teleports:
            old = (turtle.x, turtle.y)
            if kind == 'relative':
                angle = turtle.theta + theta
                x, y = turtle.x + math.cos(angle) * a, turtle.y + math.sin(angle) * a
            else:
                angle, x, y = theta, a, min(b, self.height)  # ROS: max(0, height - y) on screen
            self._place(turtle, x, y, angle)
            if turtle.pen.on:
                self.canvas.line(self.to_pixels(*old), self.to_pixels(turtle.x, turtle.y),
                                 turtle.pen.color, turtle.pen.width)
        turtle.teleports.clear()

    def _run_rotation(self, turtle: Turtle, events: list[Event]) -> None:
        rotation = turtle.rotation
        if rotation is None:
            return
        if rotation.cancel_requested():
            turtle.rotation = None
            turtle.lin_x = turtle.lin_y = turtle.ang = 0.0
            events.append(Event('canceled', turtle.name, rotation))
            return
        theta = wrap_angle(rotation.target)
        remaining = wrap_angle(theta - turtle.theta)
        rotation.delta = wrap_angle(rotation.start - turtle.theta)
        events.append(Event('feedback', turtle.name, (rotation, remaining)))
        turtle.lin_x = turtle.lin_y = 0.0
        if abs(wrap_angle(turtle.theta - theta)) < ROTATE_TOLERANCE:
            turtle.rotation = None
            turtle.ang = 0.0
            events.append(Event('succeeded', turtle.name, rotation))
        else:
            turtle.ang = -ROTATE_SPEED if remaining < 0.0 else ROTATE_SPEED
            turtle.last_command = self.time

    def _settle(self, turtle: Turtle, old_x: float, old_y: float, events: list[Event]) -> None:
        """After pymunk's step: wrap the heading, report a wall hit, clamp what is reported."""
        body = turtle.body
        vx, vy = turtle.world_velocity()
        bx, by = float(body.position.x), float(body.position.y)
        wanted_x, wanted_y = old_x + vx * self.dt, old_y + vy * self.dt
        if not (0.0 <= wanted_x <= self.width and 0.0 <= wanted_y <= self.height) or \
                not (0.0 <= bx <= self.width and 0.0 <= by <= self.height):
            # ROS reports where its integration put the turtle, in screen coordinates (y down).
            events.append(Event('wall', turtle.name, (wanted_x, self.height - wanted_y)))
        x = min(max(bx, 0.0), self.width)
        y = min(max(by, 0.0), self.height)
        theta = wrap_angle(float(body.angle))
        if abs(bx - x) > _SNAP_DISTANCE or abs(by - y) > _SNAP_DISTANCE:
            self._place(turtle, x, y, theta)
        elif theta != body.angle:
            body.angle = theta
        turtle.x, turtle.y = x, y

    def _place(self, turtle: Turtle, x: float, y: float, theta: float) -> None:
        turtle.body.position = (x, y)
        turtle.body.angle = wrap_angle(theta)
        turtle.x, turtle.y = x, y
        self.space.reindex_shapes_for_body(turtle.body)

    # -- drawing ------------------------------------------------------------------------------
    def to_pixels(self, x: float, y: float) -> tuple[float, float]:
        """World metres (y up) to canvas pixels (y down)."""
        return (x * METER_PX, (self.height - y) * METER_PX)

    def clear(self) -> None:
        self.canvas.clear()

    def render(self) -> Any:
        """The canvas with every turtle drawn on it, as a (500, 500, 3) uint8 array."""
        sprites = [Sprite(*self.to_pixels(t.x, t.y), t.theta, t.shell) for t in self.turtles.values()]
        return self.canvas.render(sprites)


def _velocity_control(turtle: Turtle) -> Callable[[pymunk.Body, Any, float, float], None]:
    """pymunk velocity function: the body moves at its commanded velocity (the contact solver,
    which runs after this, removes what would push into a wall)."""
    def velocity_func(body: pymunk.Body, gravity: Any, damping: float, dt: float) -> None:
        body.velocity = turtle.world_velocity()
        body.angular_velocity = turtle.ang
    return velocity_func


def _touching(body: pymunk.Body) -> bool:
    touching = False

    def seen(arbiter: Any) -> None:
        nonlocal touching
        touching = True
    body.each_arbiter(seen)
    return touching
