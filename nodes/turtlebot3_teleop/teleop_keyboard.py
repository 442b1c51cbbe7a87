"""teleop_keyboard: drive a TurtleBot3 from the keyboard, as turtlebot3_teleop's teleop_keyboard.

    export TURTLEBOT3_MODEL=burger
    zros run turtlebot3_teleop teleop_keyboard

w/x raise/lower the target linear speed by 0.01 m/s, a/d the target angular speed by 0.1 rad/s,
within the model's limits (burger 0.22 m/s and 2.84 rad/s; waffle and waffle_pi 0.26 and 1.82);
space or s stops; Ctrl-C quits (after sending a stop). The command sent on `cmd_vel` moves
towards the target by at most half a step per loop, and goes out on every loop (about 10 Hz,
keys or not), as TurtleBot3's does: `Twist` when ROS_DISTRO is humble or unset (zros's default,
the courses' distribution), `TwistStamped` for any other ROS_DISTRO (Jazzy and later).
The terminal handling is turtlesim's teleop's (nodes/turtlesim/turtle_teleop_key.py).
"""
from __future__ import annotations

import os
import sys

import zros
from zros.executors import ExternalShutdownException
from zros.node import Node

from interfaces.geometry_msgs.msg import Twist, TwistStamped

from nodes.turtlesim.turtle_teleop_key import KeyboardReader, run_with_keyboard

__all__ = ['TeleopKeyboard', 'LIMITS', 'LIN_VEL_STEP_SIZE', 'ANG_VEL_STEP_SIZE', 'INSTRUCTIONS', 'main']

#: TURTLEBOT3_MODEL -> (max linear [m/s], max angular [rad/s]); other names get the waffle's.
LIMITS = {'burger': (0.22, 2.84), 'waffle': (0.26, 1.82), 'waffle_pi': (0.26, 1.82)}
LIN_VEL_STEP_SIZE = 0.01
ANG_VEL_STEP_SIZE = 0.1
#: Keys that change a target count towards re-printing the instructions every this many.
REPRINT_EVERY = 20

INSTRUCTIONS = """
Control Your TurtleBot3!
---------------------------
Moving around:
        w
   a    s    d
        x

w/x : increase/decrease linear velocity (Burger : ~ 0.22, Waffle and Waffle Pi : ~ 0.26)
a/d : increase/decrease angular velocity (Burger : ~ 2.84, Waffle and Waffle Pi : ~ 1.82)

space key, s : force stop

CTRL-C to quit
"""


def _clamp(value: float, limit: float) -> float:
    return max(-limit, min(limit, value))


def _slew(output: float, target: float, slop: float) -> float:
    """Move `output` towards `target` by at most `slop`."""
    if target > output:
        return min(target, output + slop)
    if target < output:
        return max(target, output - slop)
    return target


class TeleopKeyboard(Node):

    def __init__(self, model: str, stamped: bool) -> None:
        super().__init__('teleop_keyboard')
        self.max_linear, self.max_angular = LIMITS.get(model, LIMITS['waffle'])
        self.stamped = stamped
        self.publisher = self.create_publisher(TwistStamped if stamped else Twist, 'cmd_vel', 10)
        self.target_linear = self.target_angular = 0.0
        self.control_linear = self.control_angular = 0.0
        self._changes = 0

    def handle_key(self, key: str) -> None:
        """Update the targets for one key (printing them as TurtleBot3's teleop does)."""
        if key in ('w', 'x', 'a', 'd'):
            if key in ('w', 'x'):
                step = LIN_VEL_STEP_SIZE if key == 'w' else -LIN_VEL_STEP_SIZE
                self.target_linear = _clamp(self.target_linear + step, self.max_linear)
            else:
                step = ANG_VEL_STEP_SIZE if key == 'a' else -ANG_VEL_STEP_SIZE
                self.target_angular = _clamp(self.target_angular + step, self.max_angular)
            self._changes += 1
            self._print_targets()
        elif key in (' ', 's'):
            self.target_linear = self.control_linear = 0.0
            self.target_angular = self.control_angular = 0.0
            self._print_targets()
        if self._changes == REPRINT_EVERY:
            print(INSTRUCTIONS, flush=True)
            self._changes = 0

    def _print_targets(self) -> None:
        print(f'currently:\tlinear velocity {self.target_linear}\t angular velocity {self.target_angular} ',
              flush=True)

    def publish_control(self) -> None:
        """One loop's command: the outputs slewed half a step towards the targets."""
        self.control_linear = _slew(self.control_linear, self.target_linear, LIN_VEL_STEP_SIZE / 2.0)
        self.control_angular = _slew(self.control_angular, self.target_angular, ANG_VEL_STEP_SIZE / 2.0)
        self.publish_twist(self.control_linear, self.control_angular)

    def publish_twist(self, linear: float, angular: float) -> None:
        if self.stamped:
            msg = TwistStamped()
            msg.header.stamp = self.get_clock().now().to_msg()
            twist = msg.twist
        else:
            msg = twist = Twist()
        twist.linear.x, twist.angular.z = float(linear), float(angular)
        self.publisher.publish(msg)


def key_loop(node: TeleopKeyboard, reader: KeyboardReader) -> None:
    print(INSTRUCTIONS, flush=True)
    try:
        while zros.ok() and not reader.eof:
            byte = reader.read_one()
            if byte == 0x03:          # Ctrl-C as a byte (a pipe, or a terminal without signals)
                break
            if byte is not None:
                node.handle_key(chr(byte))
            node.publish_control()
    finally:
        if zros.ok():
            node.publish_twist(0.0, 0.0)      # never leave the robot driving


def main(args: list[str] | None = None) -> int:
    model = os.environ.get('TURTLEBOT3_MODEL', '')
    if not model:
        print("TURTLEBOT3_MODEL is not set; using the burger's limits (export TURTLEBOT3_MODEL=burger)",
              file=sys.stderr)
        model = 'burger'
    stamped = os.environ.get('ROS_DISTRO', 'humble') not in ('humble', '')
    code = 0
    try:
        with zros.init(args=args):
            node = TeleopKeyboard(model, stamped)
            code = run_with_keyboard(node, lambda reader: key_loop(node, reader))
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    return code


if __name__ == '__main__':
    sys.exit(main(sys.argv))
