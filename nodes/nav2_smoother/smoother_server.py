"""nav2_smoother's smoother_server: the `smooth_path` action with Nav2's SimpleSmoother.

    zros run nav2_smoother smoother_server --ros-args --params-file nav2_params.yaml

A lifecycle node. Parameters as Nav2's: `smoother_plugins` (default `simple_smoother`), and per
smoother `<id>.plugin` (any name is served by SimpleSmoother, said so at start-up),
`<id>.tolerance`, `<id>.max_its`, `<id>.w_data`, `<id>.w_smooth`, `<id>.do_refinement`,
`<id>.refinement_num`; `costmap_topic` (`global_costmap/costmap_raw`), whose costmap keeps the
smoothing out of obstacles and checks the result when the goal asks `check_for_collisions`
(`footprint_topic`, `robot_base_frame` and `transform_tolerance` are read and unused: the
footprint is the costmap's inflated radius). The smoothed path is also published on
`plan_smoothed`. A smoothing that runs out of `max_smoothing_duration` or `max_its`, or stops
at an obstacle, still succeeds, with the last admissible path and `was_completed` false, as in
Humble; an unknown smoother id, an empty path or a path in collision abort with Nav2 Iron's
error codes (INVALID_SMOOTHER, INVALID_PATH, SMOOTHED_PATH_IN_COLLISION).
"""
from __future__ import annotations

import sys
import time
from typing import Any

import numpy as np

import zros
from zros.executors import ExternalShutdownException, spin_nodes
from zros.lifecycle import LifecycleNode
from zros.navigation.costmap import INSCRIBED_INFLATED_OBSTACLE
from zros.navigation.costmap_ros import CostmapSubscriber
from zros.navigation.node_support import Nav2Params, duration_msg, quaternion_of, yaw_of
from zros.navigation.path_smoother import SimpleSmootherParams, smooth_path
from zros.navigation.servers import GoalRunner, gated_action_server, RESULT_TIMEOUT_S

from interfaces.nav2_msgs.action import SmoothPath
from interfaces.nav_msgs.msg import Path

_SIMPLE_SMOOTHER = 'nav2_smoother::SimpleSmoother'


class SmootherServer(LifecycleNode):
    def __init__(self) -> None:
        super().__init__('smoother_server')
        prm = Nav2Params(self)
        self.smoother_ids = prm.get('smoother_plugins', ['simple_smoother']) or ['simple_smoother']
        self.smoothers: dict[str, SimpleSmootherParams] = {}
        for sid in self.smoother_ids:
            plugin = prm.get(f'{sid}.plugin', _SIMPLE_SMOOTHER)
            if plugin not in (_SIMPLE_SMOOTHER, 'nav2_smoother/SimpleSmoother'):
                self.get_logger().info(f'{sid}: {plugin} is not implemented in zros; smoothing with SimpleSmoother')
            params = SimpleSmootherParams()
            for name in SimpleSmootherParams.names():
                setattr(params, name, prm.get(f'{sid}.{name}', getattr(params, name)))
            self.smoothers[sid] = params
        costmap_topic = prm.get('costmap_topic', 'global_costmap/costmap_raw')
        for unused in ('footprint_topic', 'robot_base_frame', 'transform_tolerance'):
            prm.get(unused, '')
        result_timeout = prm.get('action_server_result_timeout', RESULT_TIMEOUT_S)
        prm.report_unused()
        self.costmap = CostmapSubscriber(self, costmap_topic)
        self.goals = GoalRunner(self)
        self.plan_pub = self.create_lifecycle_publisher(Path, 'plan_smoothed', 1)
        gated_action_server(self, SmoothPath, 'smooth_path', self._smooth, result_timeout=result_timeout)

    def _smooth(self, handle: Any) -> Any:
        goal = handle.request
        result = SmoothPath.Result()
        started = time.monotonic()
        sid = goal.smoother_id
        if not sid and len(self.smoothers) == 1:
            sid = self.smoother_ids[0]
        if sid not in self.smoothers:
            return self.goals.fail(handle, result, SmoothPath.Result.INVALID_SMOOTHER,
                                   f'SmoothPath called with smoother name {goal.smoother_id}, which does not exist. '
                                   f'Available smoothers are: {" ".join(self.smoother_ids)}.')
        poses = goal.path.poses
        if not poses:
            return self.goals.fail(handle, result, SmoothPath.Result.INVALID_PATH, 'Requested path to smooth is empty')
        points = np.array([[p.pose.position.x, p.pose.position.y] for p in poses], np.float64)
        yaws = np.array([yaw_of(p.pose.orientation) for p in poses])
        cost_at = self._cost_lookup(goal.path.header.frame_id)
        limit = goal.max_smoothing_duration.sec + goal.max_smoothing_duration.nanosec / 1e9
        smoothed = smooth_path(points, yaws, self.smoothers[sid], cost_at=cost_at, max_time=limit)
        result.path = _with_poses(goal.path, smoothed.points, smoothed.yaws)
        result.was_completed = smoothed.completed
        result.smoothing_duration = duration_msg(time.monotonic() - started)
        if not smoothed.completed:
            self.get_logger().info(f'Smoother {sid} did not complete smoothing in specified time limit '
                                   f'({limit:f} seconds) and was interrupted after '
                                   f'{time.monotonic() - started:f} seconds')
        self.plan_pub.publish(result.path)
        if goal.check_for_collisions:
            if cost_at is None:
                self.get_logger().warn('check_for_collisions: no costmap in the path\'s frame to check against')
            else:
                costs = cost_at(smoothed.points)
                hit = np.flatnonzero(costs >= INSCRIBED_INFLATED_OBSTACLE)
                if hit.size:
                    x, y = smoothed.points[hit[0]]
                    return self.goals.fail(handle, result, SmoothPath.Result.SMOOTHED_PATH_IN_COLLISION,
                                           f'Smoothed path leads to a collision at x: {x:f}, y: {y:f}, '
                                           f'theta: {smoothed.yaws[hit[0]]:f}')
        handle.succeed()
        return result

    def _cost_lookup(self, frame: str) -> Any:
        """The costmap's cost_at if it is in the path's frame (None: smooth without obstacles)."""
        costmap_frame = self.costmap.frame_id
        if costmap_frame is None:
            self.get_logger().warn('No costmap received yet: smoothing without obstacle checks',
                                   throttle_duration_sec=10.0)
            return None
        if frame and costmap_frame and frame != costmap_frame:
            self.get_logger().warn(f'The path is in {frame}, the costmap in {costmap_frame}: '
                                   'smoothing without obstacle checks', throttle_duration_sec=10.0)
            return None
        return self.costmap.cost_at


def _with_poses(path: Any, points: np.ndarray, yaws: np.ndarray) -> Any:
    """A nav_msgs/Path with `path`'s header and poses, the poses moved (in place) to `points`, `yaws`."""
    out = Path()
    out.header = path.header
    poses = []
    for pose, (x, y), yaw in zip(path.poses, points.tolist(), yaws.tolist()):
        pose.pose.position.x, pose.pose.position.y = x, y
        quaternion_of(yaw, pose.pose.orientation)
        poses.append(pose)
    out.poses = poses
    return out


def main(args: list[str] | None = None) -> int:
    try:
        with zros.init(args=args):
            spin_nodes(SmootherServer())
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    return 0


if __name__ == '__main__':
    sys.exit(main())
