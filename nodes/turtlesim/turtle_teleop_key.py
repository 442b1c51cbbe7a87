"""turtle_teleop_key: drive turtle1 from the keyboard, as ROS 2's teleop_turtle_key.

Arrow keys publish a Twist on `turtle1/cmd_vel` (scaled by the `scale_linear` and
`scale_angular` parameters, 2.0 each); g b v c d e r t send rotate_absolute goals to the eight
directions around f, which cancels the current goal; q quits. Keys are matched byte by byte
as ROS does (an arrow key is ESC [ A..D and the final byte decides).

The terminal is put in non-canonical, no-echo mode while the node runs and restored on every
way out: q, Ctrl-C, SIGTERM, or an exception. Without a terminal on stdin (a pipe), keys are
read as they come and end of input quits.
"""
from __future__ import annotations

import os
import select
import sys
import threading
from typing import Any, Callable

import zros
from zros.action import ActionClient
from zros.executors import ExternalShutdownException, SingleThreadedExecutor
from zros.node import Node

from interfaces.geometry_msgs.msg import Twist
from interfaces.turtlesim.action import RotateAbsolute

__all__ = ['TeleopTurtle', 'KeyboardReader', 'KEYS', 'INSTRUCTIONS', 'run_with_keyboard', 'main']

INSTRUCTIONS = (
    'Reading from keyboard\n'
    '---------------------------\n'
    'Use arrow keys to move the turtle.\n'
    "Use g|b|v|c|d|e|r|t keys to rotate to absolute orientations. 'f' to cancel a rotation.\n"
    "'q' to quit."
)

# byte -> (linear, angular) for the arrows, a goal angle for the rotation keys, or a command.
KEYS: dict[int, Any] = {
    0x41: ('move', 1.0, 0.0),     # up    (ESC [ A)
    0x42: ('move', -1.0, 0.0),    # down  (ESC [ B)
    0x43: ('move', 0.0, -1.0),    # right (ESC [ C)
    0x44: ('move', 0.0, 1.0),     # left  (ESC [ D)
    ord('g'): ('rotate', 0.0),
    ord('t'): ('rotate', 0.7854),
    ord('r'): ('rotate', 1.5708),
    ord('e'): ('rotate', 2.3562),
    ord('d'): ('rotate', 3.1416),
    ord('c'): ('rotate', -2.3562),
    ord('v'): ('rotate', -1.5708),
    ord('b'): ('rotate', -0.7854),
    ord('f'): ('cancel',),
    ord('q'): ('quit',),
}


class KeyboardReader:
    """Reads one byte at a time from a file descriptor, in raw-ish mode while in its `with`.

    Like ROS's KeyboardReader: ICANON and ECHO off, VMIN 0 and VTIME 1, so a read returns
    after 0.1 s without a key; signals (Ctrl-C) still work. The old mode comes back on exit.
    """

    def __init__(self, fd: int = 0) -> None:
        self.fd = fd
        self._saved: list | None = None
        self.eof = False

    def __enter__(self) -> 'KeyboardReader':
        if os.isatty(self.fd):
            import termios
            self._saved = termios.tcgetattr(self.fd)
            raw = termios.tcgetattr(self.fd)
            raw[3] &= ~(termios.ICANON | termios.ECHO)
            raw[6][termios.VMIN] = 0
            raw[6][termios.VTIME] = 1
            termios.tcsetattr(self.fd, termios.TCSANOW, raw)
        return self

    def restore(self) -> None:
        """Put the terminal back as it was (idempotent)."""
        if self._saved is not None:
            import termios
            try:
                termios.tcsetattr(self.fd, termios.TCSANOW, self._saved)
            except termios.error:
                pass
            self._saved = None

    def __exit__(self, *exc: object) -> None:
        self.restore()

    def read_one(self) -> int | None:
        """The next byte, or None when none came within about 0.1 s (or at end of input)."""
        if self._saved is None:  # not a terminal: wait for data ourselves
            ready, _, _ = select.select([self.fd], [], [], 0.1)
            if not ready:
                return None
        data = os.read(self.fd, 1)
        if not data:
            if self._saved is None:
                self.eof = True
            return None
        return data[0]


class TeleopTurtle(Node):

    def __init__(self) -> None:
        super().__init__('teleop_turtle', parameter_event_qos_overrides=True)   # a C++ node in ROS
        self.declare_parameter('scale_angular', 2.0)
        self.declare_parameter('scale_linear', 2.0)
        self.twist_pub = self.create_publisher(Twist, 'turtle1/cmd_vel', 7)
        self.rotate_client = ActionClient(self, RotateAbsolute, 'turtle1/rotate_absolute')
        self._goal_handle: Any = None

    def handle_key(self, key: int) -> bool:
        """Act on one byte; False means quit."""
        binding = KEYS.get(key)
        if binding is None:
            return True  # other keys, and ESC and '[' of an arrow, are ignored
        self.get_logger().debug(f'value: 0x{key:02X}')
        if binding[0] == 'quit':
            return False
        if binding[0] == 'move':
            _, linear, angular = binding
            twist = Twist()
            twist.linear.x = self.get_parameter('scale_linear').value * linear
            twist.angular.z = self.get_parameter('scale_angular').value * angular
            self.twist_pub.publish(twist)
        elif binding[0] == 'rotate':
            self.send_goal(binding[1])
        elif binding[0] == 'cancel':
            self.cancel_goal()
        return True

    def send_goal(self, theta: float) -> None:
        future = self.rotate_client.send_goal_async(RotateAbsolute.Goal(theta=theta))

        def on_response(done: Any) -> None:
            if done.exception() is None:
                self.get_logger().debug('Goal response received')
                self._goal_handle = done.result()
        future.add_done_callback(on_response)

    def cancel_goal(self) -> None:
        if self._goal_handle is not None:
            self.get_logger().debug('Sending cancel request')
            try:
                self._goal_handle.cancel_goal_async()
            except Exception:  # noqa: BLE001 - the goal may have ended and expired already
                pass


def key_loop(node: TeleopTurtle, reader: KeyboardReader) -> None:
    print(INSTRUCTIONS, flush=True)
    while zros.ok() and not reader.eof:
        key = reader.read_one()
        if key is not None and not node.handle_key(key):
            break


def run_with_keyboard(node: Node, loop: Callable[[KeyboardReader], None]) -> int:
    """Spin `node` on a background thread while `loop(reader)` reads keys from stdin on this one
    (teleop nodes: turtlesim's and turtlebot3_teleop's). Returns the exit code: 1 when the
    terminal cannot be read. KeyboardInterrupt (Ctrl-C) passes through, after the spin stops."""
    executor = SingleThreadedExecutor()
    executor.add_node(node)
    spinner = threading.Thread(target=_spin, args=(executor,), name='teleop-spin', daemon=True)
    spinner.start()
    try:
        with KeyboardReader(sys.stdin.fileno()) as reader:
            loop(reader)
    except OSError as exc:
        print(f'read(): {exc}', file=sys.stderr)
        return 1
    finally:
        executor.shutdown(timeout_sec=1.0)
    return 0


def main(args: list[str] | None = None) -> int:
    code = 0
    try:
        with zros.init(args=args):
            node = TeleopTurtle()
            code = run_with_keyboard(node, lambda reader: key_loop(node, reader))
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    return code


def _spin(executor: SingleThreadedExecutor) -> None:
    try:
        executor.spin()
    except ExternalShutdownException:
        pass
    except Exception:  # noqa: BLE001 - the key loop ends with the context anyway
        pass


if __name__ == '__main__':
    sys.exit(main(sys.argv))
