"""nav2_velocity_smoother's velocity_smoother: the controller's commands, rate- and
acceleration-limited, on to the robot.

    zros run nav2_velocity_smoother velocity_smoother --ros-args --params-file nav2_params.yaml

Subscribes `cmd_vel` and publishes `cmd_vel_smoothed` every 1 / `smoothing_frequency` s; Nav2's
navigation_launch.py remaps them to `cmd_vel_nav` (what the controller publishes) and `cmd_vel`
(Humble; Jazzy sends them through the collision_monitor), so without this node a robot under
Nav2's launch files never moves. A lifecycle node: it publishes only while active.

Parameters as Nav2's (zros.navigation.velocity_smoother.VelocitySmootherParams): `smoothing_frequency`,
`scale_velocities`, `feedback` (OPEN_LOOP, or CLOSED_LOOP with `odom_topic` averaged over
`odom_duration`), `max_velocity`, `min_velocity`, `max_accel`, `max_decel`, `deadband_velocity`,
`velocity_timeout` (no command for this long: the robot is brought to zero, then nothing is
sent). `use_realtime_priority` is read and ignored. A bad parameter fails `configure` with a
one-line reason.
"""
from __future__ import annotations

import sys
import threading
from collections import deque
from typing import Any

import numpy as np

import zros
from zros.executors import ExternalShutdownException
from zros.lifecycle import LifecycleNode, State, TransitionCallbackReturn
from zros.navigation.node_support import Nav2Params
from zros.navigation.velocity_smoother import VelocitySmoother, VelocitySmootherParams, twist_vector

from interfaces.geometry_msgs.msg import Twist
from interfaces.nav_msgs.msg import Odometry


class VelocitySmootherNode(LifecycleNode):
    def __init__(self) -> None:
        super().__init__('velocity_smoother')
        prm = Nav2Params(self)
        self.params = VelocitySmootherParams()
        for name in VelocitySmootherParams.names():
            setattr(self.params, name, prm.get(name, getattr(self.params, name)))
        prm.get('use_realtime_priority', False)
        prm.report_unused()
        self.smoother: VelocitySmoother | None = None
        self._lock = threading.Lock()
        self._odom: deque[tuple[float, np.ndarray]] = deque(maxlen=200)
        self._timer: Any = None
        self.cmd_pub = self.create_lifecycle_publisher(Twist, 'cmd_vel_smoothed', 1)
        self.create_subscription(Twist, 'cmd_vel', self._on_command, 1)
        if self.params.feedback == 'CLOSED_LOOP':
            self.create_subscription(Odometry, self.params.odom_topic, self._on_odom, 10)

    def on_configure(self, state: State) -> TransitionCallbackReturn:
        try:
            self.smoother = VelocitySmoother(self.params)
        except ValueError as exc:
            self.get_logger().error(f'Cannot configure: {exc}')
            return TransitionCallbackReturn.FAILURE
        return super().on_configure(state)

    def on_activate(self, state: State) -> TransitionCallbackReturn:
        self._timer = self.create_timer(1.0 / self.params.smoothing_frequency, self._smooth)
        return super().on_activate(state)

    def on_deactivate(self, state: State) -> TransitionCallbackReturn:
        if self._timer is not None:
            self.destroy_timer(self._timer)
            self._timer = None
        with self._lock:
            self.smoother.reset()
        return super().on_deactivate(state)

    def _now(self) -> float:
        return self.get_clock().now().nanoseconds / 1e9

    def _on_command(self, msg: Any) -> None:
        if self.smoother is None or self.current_state.label != 'active':
            return
        with self._lock:
            accepted = self.smoother.command(twist_vector(msg), self._now())
        if not accepted:
            self.get_logger().error('Velocity message contains NaNs or Infs! Ignoring as invalid!')

    def _on_odom(self, msg: Any) -> None:
        with self._lock:
            self._odom.append((self._now(), twist_vector(msg.twist.twist)))

    def _measured(self, now: float) -> np.ndarray | None:
        """Odometry's velocity averaged over the last `odom_duration` s (None before any arrives)."""
        recent = [v for t, v in self._odom if now - t <= self.params.odom_duration]
        if not recent:
            return self._odom[-1][1] if self._odom else None
        return np.mean(recent, axis=0)

    def _smooth(self) -> None:
        now = self._now()
        with self._lock:
            out = self.smoother.step(now, self._measured(now))
        if out is None:
            return
        twist = Twist()
        twist.linear.x, twist.linear.y, twist.angular.z = (float(v) for v in out)
        self.cmd_pub.publish(twist)


def main(args: list[str] | None = None) -> int:
    try:
        with zros.init(args=args):
            zros.spin(VelocitySmootherNode())
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    return 0


if __name__ == '__main__':
    sys.exit(main())
