"""The ROS 2 lifecycle demo's listener: a plain node (not a lifecycle one) that prints what the
lifecycle talker publishes and each transition the talker goes through.

    zros run lifecycle lifecycle_listener

It hears /lifecycle_chatter only while the talker is active, and /lc_talker/transition_event
whenever the talker changes state.
"""
from __future__ import annotations

import sys

from zros.node import Node

from interfaces.lifecycle_msgs.msg import TransitionEvent
from interfaces.std_msgs.msg import String
from nodes.lifecycle.lifecycle_talker import spin_main


class LifecycleListener(Node):
    """Logs the talker's data and its state changes."""

    def __init__(self) -> None:
        super().__init__('listener')
        self.sub_data = self.create_subscription(String, 'lifecycle_chatter', self.data_callback, 10)
        self.sub_notification = self.create_subscription(
            TransitionEvent, '/lc_talker/transition_event', self.notification_callback, 10)

    def data_callback(self, msg: String) -> None:
        self.get_logger().info(f'data_callback: {msg.data}')

    def notification_callback(self, msg: TransitionEvent) -> None:
        self.get_logger().info(f'notify callback: Transition from state {msg.start_state.label} '
                               f'to {msg.goal_state.label}')


def main(args: list[str] | None = None) -> int:
    return spin_main(LifecycleListener, args)


if __name__ == '__main__':
    sys.exit(main())
