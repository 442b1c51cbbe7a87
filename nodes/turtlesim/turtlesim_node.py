"""turtlesim_node: ROS 2's turtlesim on zros, with pymunk physics and no window.

Same names, types, parameters and log lines as ROS 2's node (see docs/turtlesim.md):
topics `<turtle>/cmd_vel`, `<turtle>/pose`, `<turtle>/color_sensor`; services `<turtle>/set_pen`,
`<turtle>/teleport_absolute`, `<turtle>/teleport_relative`, `spawn`, `kill`, `clear`, `reset`;
action `<turtle>/rotate_absolute`; parameters `background_r|g|b` and `holonomic`.
Instead of a Qt window, the picture is published as sensor_msgs/Image (rgb8, 500 x 500) on
`~/image` (`/turtlesim/image`) at 10 Hz while something subscribes; `zros view` shows it.

Threading: one MultiThreadedExecutor runs everything. The world is touched only under
`self._lock`. A rotate_absolute goal's execute callback just waits for the simulation to end
the goal, so each turning turtle holds one (idle) pool thread; the pool is sized for that.
"""
from __future__ import annotations

import sys
import threading
import time
from typing import Any

import zros
from zros.action import ActionServer, CancelResponse, GoalResponse
from zros.callback_groups import ReentrantCallbackGroup
from zros.executors import ExternalShutdownException, spin_nodes
from zros.node import Node
from zros.qos import qos_profile_sensor_data

from interfaces.geometry_msgs.msg import Twist
from interfaces.rcl_interfaces.msg import IntegerRange, ParameterDescriptor
from interfaces.sensor_msgs.msg import Image
from interfaces.std_srvs.srv import Empty
from interfaces.turtlesim.action import RotateAbsolute
from interfaces.turtlesim.msg import Color, Pose
from interfaces.turtlesim.srv import Kill, SetPen, Spawn, TeleportAbsolute, TeleportRelative

from nodes.turtlesim._world import DEFAULT_BACKGROUND, Event, Rotation, TurtleError, World

__all__ = ['TurtlesimNode', 'main']

UPDATE_PERIOD = 0.016     # ROS's update timer
IMAGE_PERIOD = 0.1        # canvas frames, while subscribed
TOPIC_QOS_DEPTH = 7       # turtlesim::topic_qos(): keep last 7
# Pool threads: a turning turtle's goal holds one while it waits; the rest serve callbacks.
EXECUTOR_THREADS = 32


class _Goal:
    """A rotate_absolute goal: its handle, and how the simulation ended it."""

    def __init__(self, handle: Any) -> None:
        self.handle = handle
        self.done = threading.Event()
        self.result = RotateAbsolute.Result()


class _TurtleEndpoints:
    """The topics, services and action of one turtle, made on spawn and destroyed on kill."""

    def __init__(self, node: 'TurtlesimNode', name: str) -> None:
        self.name = name
        self.entities: list[Any] = []
        try:
            self.pose_pub = self._keep(node.create_publisher(Pose, f'{name}/pose', TOPIC_QOS_DEPTH))
            self.color_pub = self._keep(node.create_publisher(Color, f'{name}/color_sensor', TOPIC_QOS_DEPTH))
            self._keep(node.create_subscription(Twist, f'{name}/cmd_vel',
                                                lambda msg: node._on_cmd_vel(name, msg), TOPIC_QOS_DEPTH))
            self._keep(node.create_service(SetPen, f'{name}/set_pen',
                                           lambda req, res: node._on_set_pen(name, req, res)))
            self._keep(node.create_service(TeleportRelative, f'{name}/teleport_relative',
                                           lambda req, res: node._on_teleport_relative(name, req, res)))
            self._keep(node.create_service(TeleportAbsolute, f'{name}/teleport_absolute',
                                           lambda req, res: node._on_teleport_absolute(name, req, res)))
            self.action = self._keep(ActionServer(
                node, RotateAbsolute, f'{name}/rotate_absolute', node._execute_rotation,
                callback_group=node._action_group,
                goal_callback=accept_all_goals, cancel_callback=accept_all_cancels,
                handle_accepted_callback=lambda handle: node._on_rotation_accepted(name, handle)))
        except Exception:
            self.destroy(node)
            raise

    def _keep(self, entity: Any) -> Any:
        self.entities.append(entity)
        return entity

    def destroy(self, node: Node) -> None:
        # Through the node's registry (not just entity.destroy()), so that the node forgets them
        # too: an ActionServer has no destroy_* method on Node, and spawn/kill cycles must not
        # pile up dead entities.
        for entity in reversed(self.entities):
            if not node._destroy_entity(entity):
                entity.destroy()
        self.entities.clear()


def accept_all_goals(goal_request: Any) -> GoalResponse:
    """turtlesim accepts every rotate_absolute goal (a newer one preempts the older)."""
    return GoalResponse.ACCEPT


def accept_all_cancels(goal_handle: Any) -> CancelResponse:
    """turtlesim accepts every cancel request."""
    return CancelResponse.ACCEPT


class TurtlesimNode(Node):

    def __init__(self, **kwargs: Any) -> None:
        super().__init__('turtlesim', parameter_event_qos_overrides=True, **kwargs)   # a C++ node in ROS
        self._lock = threading.RLock()
        self._world = World()
        self._endpoints: dict[str, _TurtleEndpoints] = {}
        self._goals: dict[bytes, _Goal] = {}
        self._action_group = ReentrantCallbackGroup()
        self._declare_parameters()
        self._world.canvas.background = self._background()
        self.add_post_set_parameters_callback(self._on_parameters_set)

        self.create_service(Empty, 'clear', self._on_clear)
        self.create_service(Empty, 'reset', self._on_reset)
        self.create_service(Spawn, 'spawn', self._on_spawn)
        self.create_service(Kill, 'kill', self._on_kill)
        self._image_pub = self.create_publisher(Image, '~/image', qos_profile_sensor_data)

        self.get_logger().info(f'Starting turtlesim with node name {self.get_fully_qualified_name()}')
        with self._lock:
            self._spawn('', *self._world.center(), 0.0)
        self._last_update = time.monotonic()
        self.create_timer(UPDATE_PERIOD, self._on_update)
        self.create_timer(IMAGE_PERIOD, self._on_image_timer)

    # -- parameters ----------------------------------------------------------------------------
    def _declare_parameters(self) -> None:
        for channel, default in zip('rgb', DEFAULT_BACKGROUND):
            colour = {'r': 'Red', 'g': 'Green', 'b': 'Blue'}[channel]
            self.declare_parameter(f'background_{channel}', default, ParameterDescriptor(
                description=f'{colour} channel of the background color',
                integer_range=[IntegerRange(from_value=0, to_value=255, step=1)]))
        self.declare_parameter('holonomic', False, ParameterDescriptor(
            description='If true, then turtles will be holonomic'))

    def _background(self) -> tuple[int, int, int]:
        return tuple(int(self.get_parameter(f'background_{c}').value) for c in 'rgb')  # type: ignore[return-value]

    def _on_parameters_set(self, parameters: list[Any]) -> None:
        if any(p.name.startswith('background_') for p in parameters):
            with self._lock:
                self._world.canvas.background = self._background()

    # -- global services -------------------------------------------------------------------
    def _spawn(self, name: str, x: float, y: float, theta: float) -> str:
        """Add a turtle and its endpoints (caller holds the lock); TurtleError on a bad name."""
        turtle = self._world.spawn(name, x, y, theta)
        try:
            self._endpoints[turtle.name] = _TurtleEndpoints(self, turtle.name)
        except Exception as exc:
            self._world.kill(turtle.name)
            raise TurtleError(f'Cannot spawn a turtle named [{turtle.name}]: {exc}') from exc
        self.get_logger().info(
            f'Spawning turtle [{turtle.name}] at x=[{x:f}], y=[{y:f}], theta=[{theta:f}]')
        return turtle.name

    def _remove(self, name: str) -> None:
        """Destroy a removed turtle's endpoints (the caller has ended its rotation goal)."""
        endpoints = self._endpoints.pop(name, None)
        if endpoints is not None:
            endpoints.destroy(self)

    def _on_spawn(self, request: Any, response: Any) -> Any:
        with self._lock:
            response.name = self._spawn(request.name, request.x, request.y, request.theta)
        return response

    def _on_kill(self, request: Any, response: Any) -> Any:
        with self._lock:
            turtle = self._world.kill(request.name)
            if turtle.rotation is not None:
                self._end_goal(turtle.rotation, 'abort')
            self._remove(request.name)
        return response

    def _on_clear(self, request: Any, response: Any) -> Any:
        self.get_logger().info('Clearing turtlesim.')
        with self._lock:
            self._world.clear()
        return response

    def _on_reset(self, request: Any, response: Any) -> Any:
        self.get_logger().info('Resetting turtlesim.')
        with self._lock:
            for turtle in self._world.reset():
                if turtle.rotation is not None:
                    self._end_goal(turtle.rotation, 'abort')
                self._remove(turtle.name)
            self._spawn('', *self._world.center(), 0.0)
        return response

    # -- per-turtle topics and services ------------------------------------------------------
    def _on_cmd_vel(self, name: str, msg: Any) -> None:
        holonomic = bool(self.get_parameter('holonomic').value)
        with self._lock:
            if not self._world.has_turtle(name):
                return
            interrupted = self._world.command(name, msg.linear.x, msg.linear.y if holonomic else 0.0,
                                              msg.angular.z)
            if interrupted is not None:
                self.get_logger().warn('Velocity command received during rotation goal. Aborting goal')
                self._end_goal(interrupted, 'abort')

    def _on_set_pen(self, name: str, request: Any, response: Any) -> Any:
        with self._lock:
            self._world.set_pen(name, request.r, request.g, request.b, request.width, bool(request.off))
        return response

    def _on_teleport_absolute(self, name: str, request: Any, response: Any) -> Any:
        with self._lock:
            self._world.teleport_absolute(name, request.x, request.y, request.theta)
        return response

    def _on_teleport_relative(self, name: str, request: Any, response: Any) -> Any:
        with self._lock:
            self._world.teleport_relative(name, request.linear, request.angular)
        return response

    # -- rotate_absolute -----------------------------------------------------------------------
    def _on_rotation_accepted(self, name: str, handle: Any) -> None:
        goal = _Goal(handle)
        key = bytes(handle.goal_id.uuid)
        with self._lock:
            self._goals[key] = goal
        handle.execute()  # EXECUTING now; the execute callback waits for the simulation
        with self._lock:
            if not self._world.has_turtle(name):
                self._end_goal_direct(goal, 'abort')
                return
            previous = self._world.start_rotation(name, handle.request.theta, goal,
                                                  lambda: handle.is_cancel_requested)
            if previous is not None:
                self.get_logger().warn(
                    'Rotation goal received before a previous goal finished. Aborting previous goal')
                self._end_goal(previous, 'abort')

    def _execute_rotation(self, handle: Any) -> Any:
        key = bytes(handle.goal_id.uuid)
        with self._lock:
            goal = self._goals.get(key)
        if goal is None:  # pragma: no cover - accepted goals are registered before they execute
            handle.abort()
            return RotateAbsolute.Result()
        while not goal.done.wait(0.25):
            if not self.context.ok():
                break
        with self._lock:
            self._goals.pop(key, None)
        return goal.result

    def _end_goal(self, rotation: Rotation, outcome: str) -> None:
        goal: _Goal = rotation.token
        goal.result.delta = float(rotation.delta)
        self._end_goal_direct(goal, outcome)

    @staticmethod
    def _end_goal_direct(goal: _Goal, outcome: str) -> None:
        handle = goal.handle
        try:
            if outcome == 'succeed':
                handle.succeed()
            elif outcome == 'cancel':
                handle.canceled()
            else:
                handle.abort()
        except RuntimeError:
            pass  # already finished (e.g. the server was destroyed with the turtle)
        goal.done.set()

    # -- simulation -----------------------------------------------------------------------------
    def _on_update(self) -> None:
        now = time.monotonic()
        with self._lock:
            elapsed, self._last_update = now - self._last_update, now
            for events in self._world.advance(elapsed):
                self._publish(events)

    def _publish(self, events: list[Event]) -> None:
        for event in events:
            endpoints = self._endpoints.get(event.turtle)
            if event.kind == 'pose' and endpoints is not None:
                x, y, theta, linear, angular = event.data
                endpoints.pose_pub.publish(Pose(x=x, y=y, theta=theta, linear_velocity=linear,
                                                angular_velocity=angular))
            elif event.kind == 'color' and endpoints is not None:
                r, g, b = event.data
                endpoints.color_pub.publish(Color(r=r, g=g, b=b))
            elif event.kind == 'wall':
                x, y = event.data
                self.get_logger().warn(f'Oh no! I hit the wall! (Clamping from [x={x:f}, y={y:f}])')
            elif event.kind == 'feedback':
                rotation, remaining = event.data
                handle = rotation.token.handle
                if handle.is_active:
                    try:
                        handle.publish_feedback(RotateAbsolute.Feedback(remaining=float(remaining)))
                    except RuntimeError:
                        pass  # the action server went away with its turtle
            elif event.kind == 'succeeded':
                self.get_logger().info('Rotation goal completed successfully')
                self._end_goal(event.data, 'succeed')
            elif event.kind == 'canceled':
                self.get_logger().info('Rotation goal canceled')
                self._end_goal(event.data, 'cancel')

    def _on_image_timer(self) -> None:
        if self._image_pub.get_subscription_count() == 0:
            return
        with self._lock:
            frame = self._world.render()
        self._image_pub.publish(self.make_image(frame))

    def make_image(self, frame: Any) -> Image:
        """The canvas as sensor_msgs/Image (rgb8); the pixels are not copied."""
        height, width = frame.shape[:2]
        msg = Image(height=height, width=width, encoding='rgb8', is_bigendian=0, step=width * 3,
                    data=frame.reshape(-1))
        msg.header.stamp = self.get_clock().now().to_msg()
        msg.header.frame_id = self.get_name()
        return msg

    def destroy_node(self) -> None:
        with self._lock:
            for turtle in self._world.turtles.values():
                if turtle.rotation is not None:
                    self._end_goal(turtle.rotation, 'abort')
                    turtle.rotation = None
        super().destroy_node()


def main(args: list[str] | None = None) -> None:
    try:
        with zros.init(args=args):
            spin_nodes(TurtlesimNode(), num_threads=EXECUTOR_THREADS)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass


if __name__ == '__main__':
    main(sys.argv)
