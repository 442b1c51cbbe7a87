"""turtlebot3_teleop teleop_keyboard, driven through a pseudo-terminal: TurtleBot3's keys, limits,
messages, the slewed output, Twist or TwistStamped by ROS_DISTRO, and a stop on the way out."""
from __future__ import annotations

import os
import select
import subprocess
import sys
import threading
from typing import Any

import pytest

from conftest import REPO, wait_until


class Teleop:
    """teleop_keyboard on a pty, with a subscription recording what it publishes on /cmd_vel."""

    def __init__(self, context: Any, msg_type: type, env: dict[str, str]) -> None:
        from zros.node import Node
        self.twists: list[Any] = []
        self.node = Node('teleop_test', context=context)
        self.node.create_subscription(msg_type, '/cmd_vel', self._keep, 100)
        self._lock = threading.Lock()
        self.master, slave = os.openpty()
        self.proc = subprocess.Popen([sys.executable, '-m', 'zros.cli.main', 'run', 'turtlebot3_teleop',
                                      'teleop_keyboard'], stdin=slave, stdout=slave, stderr=slave, cwd=REPO,
                                     env=env, preexec_fn=_controlling_terminal)
        os.close(slave)
        self.screen = bytearray()

    def _keep(self, msg: Any) -> None:
        with self._lock:
            self.twists.append(msg)

    def text(self) -> str:
        while select.select([self.master], [], [], 0)[0]:
            try:
                data = os.read(self.master, 4096)
            except OSError:
                break
            if not data:
                break
            self.screen.extend(data)
        return self.screen.decode(errors='replace')

    def keys(self, keys: str) -> None:
        os.write(self.master, keys.encode())

    def last(self) -> tuple[float, float]:
        with self._lock:
            msg = self.twists[-1]
        twist = getattr(msg, 'twist', msg)
        return (twist.linear.x, twist.angular.z)

    def wait_command(self, linear: float, angular: float, timeout: float = 10.0) -> None:
        wait_until(lambda: self.twists and self.last() == pytest.approx((linear, angular)), timeout,
                   message=lambda: f'cmd_vel ({linear}, {angular}); last {self.twists and self.last()}')

    def close(self) -> None:
        if self.proc.poll() is None:
            self.proc.kill()
            self.proc.wait(timeout=5)
        os.close(self.master)


def _controlling_terminal() -> None:
    """In the child: make the pty its terminal, so that ^C becomes SIGINT as in a real one."""
    import fcntl
    import termios
    os.setsid()
    fcntl.ioctl(0, termios.TIOCSCTTY, 0)


def _spin(executor: Any) -> None:
    try:
        executor.spin()
    except Exception:  # noqa: BLE001 - ends with the context
        pass


@pytest.fixture
def teleop_factory(context: Any):
    from zros.executors import SingleThreadedExecutor
    executor = SingleThreadedExecutor(context=context)
    threading.Thread(target=_spin, args=(executor,), daemon=True).start()
    made: list[Teleop] = []

    def make(msg_type: type, **env: str) -> Teleop:
        environment = {k: v for k, v in os.environ.items() if k not in ('ROS_DISTRO', 'TURTLEBOT3_MODEL')}
        environment.update(env)
        teleop = Teleop(context, msg_type, environment)
        executor.add_node(teleop.node)
        made.append(teleop)
        wait_until(lambda: 'CTRL-C to quit' in teleop.text(), 20, message=lambda: f'the instructions; got {teleop.text()!r}')
        wait_until(lambda: teleop.twists, 10, message='the first cmd_vel (it publishes every loop)')
        return teleop
    yield make
    for teleop in made:
        teleop.close()
    executor.shutdown(timeout_sec=2)


def test_teleop_keys_give_turtlebot3s_velocities_limits_and_messages(teleop_factory: Any) -> None:
    from interfaces.geometry_msgs.msg import Twist
    teleop = teleop_factory(Twist, TURTLEBOT3_MODEL='burger')
    text = teleop.text()
    assert 'Control Your TurtleBot3!' in text and 'space key, s : force stop' in text
    assert teleop.last() == (0.0, 0.0)
    teleop.keys('www')
    teleop.keys('aa')
    teleop.wait_command(0.03, 0.2)           # reached in half steps, one per loop
    wait_until(lambda: 'currently:\tlinear velocity 0.03\t angular velocity 0.2 ' in teleop.text(), 5,
               message=lambda: f'the targets printed; got {teleop.text()[-300:]!r}')
    teleop.keys('w' * 30 + 'd' * 60)         # beyond the burger's limits
    teleop.wait_command(0.22, -2.84, timeout=20)
    assert 'linear velocity 0.22\t angular velocity -2.84' in teleop.text()
    teleop.keys(' ')
    teleop.wait_command(0.0, 0.0)
    teleop.keys('x')
    teleop.wait_command(-0.01, 0.0)
    teleop.keys('\x03')                      # Ctrl-C: quits, leaving the robot stopped
    assert teleop.proc.wait(timeout=10) == 0
    assert teleop.last() == (0.0, 0.0)


def test_teleop_sends_twist_stamped_after_humble_and_waffle_limits(teleop_factory: Any) -> None:
    from interfaces.geometry_msgs.msg import TwistStamped
    teleop = teleop_factory(TwistStamped, TURTLEBOT3_MODEL='waffle', ROS_DISTRO='jazzy')
    teleop.keys('a' * 25)
    teleop.wait_command(0.0, 1.82, timeout=20)
