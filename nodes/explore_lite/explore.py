"""explore_lite's explore: greedy frontier exploration, sending each goal to navigate_to_pose.

    zros launch explore_lite explore.launch.py use_sim_time:=True
    zros run explore_lite explore --ros-args -p use_sim_time:=true

Every 1/`planner_frequency` seconds it searches the map (`costmap_topic`, patched by
`costmap_updates_topic`) for frontiers (zros.navigation.frontiers), takes the cheapest one
not blacklisted and sends the frontier cell nearest its centroid as a NavigateToPose goal
(explore_lite sends the centroid itself, which for a frontier that wraps around a room can lie
inside an obstacle: the goal then fails and exploration stops early). A goal that fails, or
that makes no progress (the frontier's distance does not shrink) for `progress_timeout`
seconds, is blacklisted. With no frontier left it says "All frontiers traversed/tried out,
stopping." and, with `return_to_init`, drives back to where it started. `explore/resume`
(std_msgs/Bool) stops and resumes; `explore/frontiers` (MarkerArray, namespace "frontiers")
shows the frontiers when `visualize`. Parameters are explore_lite's.

Started beside a SLAM node with the robot standing still, the map may show walls but no free
space yet (zros's SLAM calls a cell free only once more than one keyframe saw through it). Then it turns the robot in place once, with the behavior server's `spin`, so that
SLAM sees the room from several headings, and explores from there (explore_lite would say
"All frontiers traversed" and stop).
"""
from __future__ import annotations

import sys
import threading
from typing import Any

import numpy as np

import zros
from zros.action import ActionClient
from zros.executors import ExternalShutdownException, spin_nodes
from zros.navigation.frontiers import Blacklist, find_frontiers
from zros.navigation.node_support import Nav2Params, lookup_pose
from zros.node import Node
from zros.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from zros.tf2_ros import Buffer, TransformListener

from interfaces.action_msgs.msg import GoalStatus
from interfaces.map_msgs.msg import OccupancyGridUpdate
from interfaces.nav2_msgs.action import NavigateToPose, Spin
from interfaces.nav_msgs.msg import OccupancyGrid
from interfaces.std_msgs.msg import Bool
from interfaces.visualization_msgs.msg import Marker, MarkerArray


class Explore(Node):
    def __init__(self) -> None:
        super().__init__('explore_node')
        prm = Nav2Params(self)
        self.robot_base_frame = prm.get('robot_base_frame', 'base_link')
        self.return_to_init = prm.get('return_to_init', False)
        costmap_topic = prm.get('costmap_topic', 'costmap')
        updates_topic = prm.get('costmap_updates_topic', 'costmap_updates')
        self.visualize = prm.get('visualize', False)
        self.planner_frequency = prm.get('planner_frequency', 1.0)
        self.progress_timeout = prm.get('progress_timeout', 30.0)
        self.potential_scale = prm.get('potential_scale', 1e-3)
        prm.get('orientation_scale', 0.0)
        self.gain_scale = prm.get('gain_scale', 1.0)
        prm.get('transform_tolerance', 0.3)
        self.min_frontier_size = prm.get('min_frontier_size', 0.5)
        prm.report_unused()
        self.tf_buffer = Buffer(node=self)
        self.tf_listener = TransformListener(self.tf_buffer, self)
        self.lock = threading.Lock()
        self.grid: Any = None
        self.data: np.ndarray | None = None
        self.blacklist: Blacklist | None = None
        self.prev_goal: tuple[float, float] | None = None
        self.prev_distance = float('inf')
        self.last_progress_ns = 0
        self.goal_handle: Any = None
        # The plan runs from the timer, the map and the goals' callbacks, on two threads: one at a
        # time, and a goal counts from when it is sent, so a second plan before the first goal's
        # acceptance neither sends it again nor lets the older acceptance win (the newer goal
        # preempts the older, whose abort would blacklist a frontier nobody tried).
        self.plan_lock = threading.RLock()
        self.sent = 0                         # goals sent; _on_accepted keeps only the last one's
        self.pending = False                  # a goal is sent and not yet accepted or rejected
        self.active = True
        self.done = False
        self.initial_pose: tuple[float, float, float] | None = None
        self.nav_client = ActionClient(self, NavigateToPose, 'navigate_to_pose')
        self.spin_client = ActionClient(self, Spin, 'spin')
        self.look_around: Any = None          # the spin's result future, once sent
        latched = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL, reliability=ReliabilityPolicy.RELIABLE)
        self.create_subscription(OccupancyGrid, costmap_topic, self._on_map, latched)
        self.create_subscription(OccupancyGridUpdate, updates_topic, self._on_update, 10)
        self.create_subscription(Bool, 'explore/resume', self._on_resume, 10)
        self.marker_pub = self.create_publisher(MarkerArray, 'explore/frontiers', 10)
        self.create_timer(1.0 / max(self.planner_frequency, 1e-3), self.make_plan)
        self.get_logger().info('Waiting for costmap to become available, topic: ' + costmap_topic)

    # -- inputs --------------------------------------------------------------------------------
    def _on_map(self, msg: Any) -> None:
        with self.lock:
            first = self.grid is None
            self.grid = msg
            self.data = np.asarray(msg.data, np.int8).reshape(msg.info.height, msg.info.width).copy()
            if self.blacklist is None:
                self.blacklist = Blacklist(msg.info.resolution)
        if first:
            self.get_logger().info('Exploration started')
            self._remember_start()
            self.make_plan()

    def _on_update(self, msg: Any) -> None:
        with self.lock:
            if self.data is None:
                return
            patch = np.asarray(msg.data, np.int8).reshape(msg.height, msg.width)
            self.data[msg.y:msg.y + msg.height, msg.x:msg.x + msg.width] = patch

    def _on_resume(self, msg: Any) -> None:
        if msg.data:
            self.get_logger().info('Exploration resumed')
            self.active, self.done = True, False
            self.make_plan()
        else:
            self.get_logger().info('Exploration stopped')
            self.stop()

    def _remember_start(self) -> None:
        try:
            self.initial_pose = lookup_pose(self.tf_buffer, self.grid.header.frame_id or 'map', self.robot_base_frame)
        except Exception:  # noqa: BLE001 - no TF yet: try again at the next plan
            self.initial_pose = None

    # -- planning ------------------------------------------------------------------------------
    def make_plan(self) -> None:
        with self.plan_lock:
            self._make_plan()

    def _make_plan(self) -> None:
        if not self.active or self.done or (self.look_around is not None and not self.look_around.done()):
            return
        with self.lock:
            if self.grid is None:
                return
            info, frame, data = self.grid.info, self.grid.header.frame_id or 'map', self.data.copy()
        if self.initial_pose is None:
            self._remember_start()
        try:
            x, y, _ = lookup_pose(self.tf_buffer, frame, self.robot_base_frame)
        except Exception as exc:  # noqa: BLE001 - tf2's exceptions
            self.get_logger().warn(f'Could not get the robot pose in {frame}: {exc}', throttle_duration_sec=5.0)
            return
        frontiers = find_frontiers(data, info.resolution, (info.origin.position.x, info.origin.position.y), (x, y),
                                   min_frontier_size=self.min_frontier_size, potential_scale=self.potential_scale,
                                   gain_scale=self.gain_scale)
        if frontiers is None:
            self._look_around()
            return
        self.get_logger().debug(f'found {len(frontiers)} frontiers')
        if self.visualize:
            self._publish_markers(frontiers, frame)
        target = next((f for f in frontiers if not self.blacklist.contains(f.goal)), None)
        if target is None:
            self.get_logger().warn('All frontiers traversed/tried out, stopping.')
            self.done = True
            self._return_to_init(frame)
            return
        now = self.get_clock().now().nanoseconds
        same = self.prev_goal is not None and np.hypot(*np.subtract(self.prev_goal, target.goal)) < 0.01
        if not same or target.min_distance < self.prev_distance:
            self.last_progress_ns = now
            self.prev_distance = target.min_distance
        if same and (now - self.last_progress_ns) / 1e9 > self.progress_timeout:
            self.blacklist.add(target.goal)
            self.get_logger().info('Adding current goal to black list')
            self.make_plan()
            return
        if same and (self.goal_handle is not None or self.pending):
            return
        self.prev_goal = target.goal
        self._send(target.goal, frame)

    def _look_around(self) -> None:
        """No free space near the robot in the map: turn in place once (module docstring)."""
        if self.look_around is not None or not self.spin_client.server_is_ready():
            self.get_logger().info('Waiting for the map to show free space around the robot', throttle_duration_sec=10.0)
            return
        self.get_logger().info('No free space around the robot in the map yet: turning in place once so that '
                               'SLAM sees around it')
        goal = Spin.Goal(target_yaw=6.28)
        goal.time_allowance.sec = 60
        self.look_around = self.spin_client.send_goal_async(goal)
        self.look_around.add_done_callback(self._on_spin_accepted)

    def _on_spin_accepted(self, future: Any) -> None:
        handle = future.result()
        if handle is not None and handle.accepted:
            self.look_around = handle.get_result_async()
            self.look_around.add_done_callback(lambda f: self.make_plan())

    def _send(self, xy: tuple[float, float], frame: str, on_done: Any = None) -> None:
        goal = NavigateToPose.Goal()
        goal.pose.header.frame_id = frame
        goal.pose.header.stamp = self.get_clock().now().to_msg()
        goal.pose.pose.position.x, goal.pose.pose.position.y = float(xy[0]), float(xy[1])
        goal.pose.pose.orientation.w = 1.0
        if not self.nav_client.server_is_ready():
            self.get_logger().warn('navigate_to_pose is not available yet', throttle_duration_sec=5.0)
            return
        with self.plan_lock:
            self.sent += 1
            self.pending = True
            number = self.sent
            future = self.nav_client.send_goal_async(goal)
        future.add_done_callback(lambda f: self._on_accepted(f, xy, on_done, number))

    def _on_accepted(self, future: Any, xy: tuple[float, float], on_done: Any, number: int) -> None:
        handle = future.result()
        with self.plan_lock:
            latest = number == self.sent
            if latest:
                self.pending = False
            if handle is None or not handle.accepted:
                self.get_logger().warn('navigate_to_pose rejected the goal')
                return
            if not latest:
                return                      # a newer goal was sent since: this one's end says nothing
            self.goal_handle = handle
        handle.get_result_async().add_done_callback(lambda f: self._on_result(f, xy, handle, on_done))

    def _on_result(self, future: Any, xy: tuple[float, float], handle: Any, on_done: Any) -> None:
        if self.goal_handle is not handle:
            return                          # superseded by a newer goal: its abort says nothing
        self.goal_handle = None
        status = future.result().status if future.result() is not None else GoalStatus.STATUS_UNKNOWN
        if on_done is not None:
            on_done(status)
            return
        if status == GoalStatus.STATUS_ABORTED:
            self.blacklist.add(xy)
            self.get_logger().debug('Goal was aborted: added to the black list')
        if self.active and not self.done:
            self.make_plan()   # replan at once, as explore_lite does on a reached goal

    def _return_to_init(self, frame: str) -> None:
        if not self.return_to_init or self.initial_pose is None:
            return
        self.get_logger().info('Returning to initial pose.')
        self._send(self.initial_pose[:2], frame,
                   on_done=lambda status: self.get_logger().info(
                       'Exploration finished, back at the initial pose.' if status == GoalStatus.STATUS_SUCCEEDED
                       else 'Could not return to the initial pose.'))

    def stop(self) -> None:
        self.active = False
        if self.goal_handle is not None:
            self.goal_handle.cancel_goal_async()

    def _publish_markers(self, frontiers: list, frame: str) -> None:
        markers = MarkerArray()
        stamp = self.get_clock().now().to_msg()
        clear = Marker(action=Marker.DELETEALL, ns='frontiers')
        clear.header.frame_id = frame
        items = [clear]
        for i, f in enumerate(frontiers):
            m = Marker(ns='frontiers', id=i, type=Marker.POINTS, action=Marker.ADD)
            m.header.frame_id, m.header.stamp = frame, stamp
            m.scale.x = m.scale.y = 0.1
            m.color.r, m.color.g, m.color.b, m.color.a = (1.0, 0.0, 0.0, 1.0) if self.blacklist.contains(f.goal) \
                else (0.0, 0.0, 1.0, 1.0)
            points = []
            for px, py in f.points.tolist():
                p = type(m.pose.position)()
                p.x, p.y = px, py
                points.append(p)
            m.points = points
            items.append(m)
        markers.markers = items
        self.marker_pub.publish(markers)


def main(args: list[str] | None = None) -> int:
    try:
        with zros.init(args=args):
            spin_nodes(Explore(), num_threads=2)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    return 0


if __name__ == '__main__':
    sys.exit(main())
