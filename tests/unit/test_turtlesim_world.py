"""turtlesim's pymunk world on its own: fixed steps, walls, command expiry, pens, spawn and kill as
ROS's turtlesim does them (turtlesim_node and its tools as processes:
tests/integration/test_turtlesim.py)."""
from __future__ import annotations

import math
from typing import Callable

import pytest

from nodes.turtlesim._world import COMMAND_TIMEOUT, DT, WORLD_SIZE, TurtleError, World


CENTER = WORLD_SIZE / 2.0


BACKGROUND = (69, 86, 255)


def _drive(world: World, name: str, seconds: float, lin: float, ang: float = 0.0,
           chunks: Callable[[int], float] = lambda i: DT) -> None:
    """Command (lin, ang) every 0.25 s of sim time and feed `seconds` of real time in chunks."""
    fed, i, next_command = 0.0, 0, 0.0
    while fed < seconds - 1e-9:
        if world.time >= next_command - 1e-9:
            world.command(name, lin, 0.0, ang)
            next_command += 0.25
        chunk = min(chunks(i), seconds - fed)
        world.advance(chunk)
        fed += chunk
        i += 1


def test_world_drives_one_metre_per_second_for_two_seconds():
    world = World()
    turtle = world.spawn('', CENTER - 3.0, CENTER, 0.0)
    assert turtle.name == 'turtle1'
    _drive(world, 'turtle1', 2.0, 1.0)
    assert turtle.x - (CENTER - 3.0) == pytest.approx(2.0, rel=0.02)
    assert turtle.y == pytest.approx(CENTER, abs=1e-9)


def test_world_steps_are_fixed_whatever_the_wall_clock_jitter():
    smooth, jittery = World(), World()
    for world in (smooth, jittery):
        world.spawn('', 3.0, 3.0, 0.3)
    _drive(smooth, 'turtle1', 1.5, 1.2, 0.7)
    pattern = [0.003, 0.041, 0.016, 0.0, 0.029, 0.011]
    _drive(jittery, 'turtle1', 1.5, 1.2, 0.7, chunks=lambda i: pattern[i % len(pattern)])
    a, b = smooth.turtles['turtle1'], jittery.turtles['turtle1']
    # Same number of steps, same physics: only the last partial slice may differ.
    assert abs(smooth.time - jittery.time) <= DT + 1e-9
    assert math.hypot(a.x - b.x, a.y - b.y) <= 1.2 * DT + 1e-6
    assert smooth.time == pytest.approx(round(1.5 / DT) * DT, abs=DT)


def test_world_wall_stops_the_turtle_with_rosss_warning():
    world = World()
    turtle = world.spawn('', WORLD_SIZE - 1.0, 4.0, 0.0)
    walls = []
    world.command('turtle1', 2.0, 0.0, 0.0)
    for _ in range(int(0.9 / DT)):
        walls += [e for step in world.advance(DT) for e in step if e.kind == 'wall']
    assert turtle.x == pytest.approx(WORLD_SIZE, abs=2e-3) and turtle.x <= WORLD_SIZE
    assert turtle.y == pytest.approx(4.0, abs=1e-6)
    assert walls, 'no wall event'
    x, y_screen = walls[-1].data
    assert x > WORLD_SIZE and y_screen == pytest.approx(WORLD_SIZE - 4.0, abs=1e-6)
    # A turtle sliding along a wall keeps its other component of motion.
    world.command('turtle1', 0.0, 0.0, 0.0)
    world.teleport_absolute('turtle1', WORLD_SIZE, 4.0, math.radians(60))
    world.advance(DT)
    _drive(world, 'turtle1', 0.5, 1.0)
    assert turtle.x == pytest.approx(WORLD_SIZE, abs=2e-3)
    assert turtle.y > 4.0 + 0.3


def test_world_velocity_command_expires_after_one_second():
    world = World()
    turtle = world.spawn('', 2.0, 2.0, 0.0)
    world.command('turtle1', 1.0, 0.0, 0.0)
    for _ in range(int(2.0 / DT)):
        world.advance(DT)
    assert turtle.x - 2.0 == pytest.approx(COMMAND_TIMEOUT, abs=2 * DT)
    assert turtle.lin_x == 0.0


def test_world_names_pen_teleport_and_clear():
    world = World()
    world.spawn('', CENTER, CENTER, 0.0)
    assert world.spawn('', 1.0, 1.0, 0.0).name == 'turtle2'
    with pytest.raises(TurtleError, match=r'A turtle named \[turtle2\] already exists'):
        world.spawn('turtle2', 1.0, 1.0, 0.0)
    world.kill('turtle2')
    with pytest.raises(TurtleError, match=r'Tried to kill turtle \[turtle2\], which does not exist'):
        world.kill('turtle2')
    assert world.spawn('', 1.0, 1.0, 0.0).name == 'turtle3'  # the counter only goes up
    # Pen off: a teleport draws nothing.
    world.set_pen('turtle1', 0, 0, 0, 0, True)
    world.teleport_absolute('turtle1', 2.0, CENTER, 0.0)
    world.advance(DT)
    assert not world.canvas.mask.any()
    # A red pen: the line appears in red, `width` pixels wide.
    world.set_pen('turtle1', 255, 0, 0, 5, False)
    world.teleport_absolute('turtle1', 8.0, CENTER, 0.0)
    world.advance(DT)
    px, py = world.to_pixels(5.0, CENTER)
    frame = world.render()
    assert tuple(frame[int(round(py)), int(px)]) == (255, 0, 0)
    assert tuple(frame[int(round(py)) + 6, int(px)]) == BACKGROUND
    assert world.canvas.pixel(px, py) == (255, 0, 0)
    world.clear()
    assert tuple(world.render()[int(round(py)), int(px)]) == BACKGROUND
    # Reset: one turtle1 in the middle again.
    world.reset()
    assert [t.name for t in (world.spawn('', CENTER, CENTER, 0.0),)] == ['turtle1']
