"""`buffer_server`: a TF buffer that other nodes query with tf2_ros.BufferClient, as tf2_ros's.

The node `tf_buffer` listens to /tf and /tf_static into a Buffer of `buffer_size` seconds
(parameter, 120 by default) and serves the action `tf2_buffer_server`
(tf2_msgs/action/LookupTransform): each goal is one lookup, waited for up to the goal's own
timeout; a lookup that fails ends the goal aborted, with the TF2Error code of the exception.
"""
from __future__ import annotations

import sys

import zros
from zros.action import ActionServer
from zros.duration import Duration
from zros.executors import ExternalShutdownException, MultiThreadedExecutor
from zros.node import Node
from zros.tf2_ros import (Buffer, ConnectivityException, ExtrapolationException, InvalidArgumentException,
                          LookupException, TimeoutException, TransformException, TransformListener)
from zros.time import Time

ACTION_NAME = 'tf2_buffer_server'

# exception -> TF2Error code (TRANSFORM_ERROR, 6, for the rest)
_CODES = ((LookupException, 1), (ConnectivityException, 2), (ExtrapolationException, 3),
          (InvalidArgumentException, 4), (TimeoutException, 5))


def error_code(exc: TransformException) -> int:
    return next((code for kind, code in _CODES if isinstance(exc, kind)), 6)


class BufferServer:
    """Serves lookups in `buffer` on the action `name` of `node`."""

    def __init__(self, buffer: Buffer, node: Node, name: str = ACTION_NAME) -> None:
        from interfaces.tf2_msgs.action import LookupTransform
        self._buffer, self._type = buffer, LookupTransform
        self.action_server = ActionServer(node, LookupTransform, name, self._execute)

    def _execute(self, goal_handle) -> object:
        request = goal_handle.request
        result = self._type.Result()
        timeout = Duration.from_msg(request.timeout)
        try:
            if request.advanced:
                result.transform = self._buffer.lookup_transform_full(
                    request.target_frame, Time.from_msg(request.target_time), request.source_frame,
                    Time.from_msg(request.source_time), request.fixed_frame, timeout)
            else:
                result.transform = self._buffer.lookup_transform(
                    request.target_frame, request.source_frame, Time.from_msg(request.source_time), timeout)
        except TransformException as exc:
            result.error.error, result.error.error_string = error_code(exc), str(exc)
            goal_handle.abort()
            return result
        goal_handle.succeed()
        return result


def main(args: list[str] | None = None) -> int:
    try:
        with zros.init(args=args):
            node = Node('tf_buffer')
            buffer_size = node.declare_parameter('buffer_size', 120.0).value
            buffer = Buffer(cache_time=Duration(seconds=buffer_size), node=node)
            TransformListener(buffer, node)
            BufferServer(buffer, node)
            executor = MultiThreadedExecutor()   # lookups wait; several may wait at once
            executor.add_node(node)
            executor.spin()
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    return 0


if __name__ == '__main__':
    sys.exit(main())
