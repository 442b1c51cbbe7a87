"""The ROS 2 lifecycle demo's talker: publishes `Lifecycle HelloWorld #N` on /lifecycle_chatter
once a second, but only while it is active.

    zros run lifecycle lifecycle_talker
    zros lifecycle set /lc_talker configure ; zros lifecycle set /lc_talker activate

Parameter `fail_on` (a callback name such as 'on_activate', default '') makes that transition
return FAILURE, to try what a manager does with a node that refuses.
"""
from __future__ import annotations

import sys
from typing import Callable

import zros
from zros.executors import ExternalShutdownException
from zros.lifecycle import LifecycleNode, State, TransitionCallbackReturn
from zros.node import Node

from interfaces.std_msgs.msg import String


class LifecycleTalker(LifecycleNode):
    def __init__(self) -> None:
        super().__init__('lc_talker')
        self.declare_parameter('fail_on', '')
        self._count = 0
        self._pub = None
        self._timer = None

    def _outcome(self, callback: str) -> TransitionCallbackReturn:
        if self.get_parameter('fail_on').value == callback:
            self.get_logger().info(f'{callback}() is told to fail')
            return TransitionCallbackReturn.FAILURE
        return TransitionCallbackReturn.SUCCESS

    def publish(self) -> None:
        self._count += 1
        msg = String(data=f'Lifecycle HelloWorld #{self._count}')
        if self._pub.is_activated:
            self.get_logger().info(f'Lifecycle publisher is active. Publishing: [{msg.data}]')
        self._pub.publish(msg)

    def on_configure(self, state: State) -> TransitionCallbackReturn:
        self._pub = self.create_lifecycle_publisher(String, 'lifecycle_chatter', 10)
        self._timer = self.create_timer(1.0, self.publish)
        self.get_logger().info(f'on_configure() is called from state {state.label}.')
        return self._outcome('on_configure')

    def on_activate(self, state: State) -> TransitionCallbackReturn:
        self.get_logger().info(f'on_activate() is called from state {state.label}.')
        result = self._outcome('on_activate')
        return super().on_activate(state) if result == TransitionCallbackReturn.SUCCESS else result

    def on_deactivate(self, state: State) -> TransitionCallbackReturn:
        self.get_logger().info(f'on_deactivate() is called from state {state.label}.')
        return super().on_deactivate(state)

    def on_cleanup(self, state: State) -> TransitionCallbackReturn:
        self.destroy_timer(self._timer)
        self.destroy_lifecycle_publisher(self._pub)
        self._timer = self._pub = None
        self.get_logger().info(f'on_cleanup() is called from state {state.label}.')
        return TransitionCallbackReturn.SUCCESS

    def on_shutdown(self, state: State) -> TransitionCallbackReturn:
        self.get_logger().info(f'on_shutdown() is called from state {state.label}.')
        return TransitionCallbackReturn.SUCCESS


def spin_main(make_node: Callable[[], Node], args: list[str] | None) -> int:
    """The lifecycle demo's executables: spin the node `make_node` builds until shut down (a
    signal or Ctrl-C ends it quietly); exit status 0."""
    try:
        with zros.init(args=args):
            zros.spin(make_node())
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    return 0


def main(args: list[str] | None = None) -> int:
    return spin_main(LifecycleTalker, args)


if __name__ == '__main__':
    sys.exit(main())
