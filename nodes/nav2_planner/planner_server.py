"""nav2_planner's planner_server: `compute_path_to_pose` and `compute_path_through_poses` on the
global costmap (which runs in this process as /global_costmap/global_costmap).

    zros run nav2_planner planner_server --ros-args --params-file burger.yaml

A lifecycle node (the navigation lifecycle manager brings it up). The planner is
zros.navigation.planner's Dijkstra on the inflated costmap (NavFn's role, any `plugin` name is
served by it); parameters as Nav2's: `expected_planner_frequency`, `planner_plugins`,
`<plugin>.tolerance`, `<plugin>.allow_unknown`. The path is also published on `/plan`.
Failures abort the goal with ComputePathToPose's error code and message (GOAL_OCCUPIED,
NO_VALID_PATH, ...).
"""
from __future__ import annotations

import sys
import time
from typing import Any

import numpy as np

import zros
from zros.executors import ExternalShutdownException, spin_nodes
from zros.lifecycle import LifecycleNode, State, TransitionCallbackReturn
from zros.navigation.costmap_ros import CostmapNode
from zros.navigation.node_support import Nav2Params, duration_msg, path_msg, pose_in_frame
from zros.navigation.planner import UNKNOWN, GridPlanner, PlanningError, path_yaws
from zros.navigation.servers import GoalRunner, gated_action_server, RESULT_TIMEOUT_S
from zros.tf2_ros import Buffer, TransformListener

from interfaces.nav2_msgs.action import ComputePathThroughPoses, ComputePathToPose
from interfaces.nav_msgs.msg import Path

_TF_ERROR = 202
_MAP_WAIT_S = 5.0


class PlannerServer(LifecycleNode):
    def __init__(self) -> None:
        super().__init__('planner_server')
        self.tf_buffer = Buffer(node=self)
        self.tf_listener = TransformListener(self.tf_buffer, self)
        prm = Nav2Params(self)
        self.expected_frequency = prm.get('expected_planner_frequency', 20.0)
        plugins = prm.get('planner_plugins', ['GridBased'])
        self.plugin_ids = plugins or ['GridBased']
        first = self.plugin_ids[0]
        self.tolerance = prm.get(f'{first}.tolerance', 0.5)
        self.allow_unknown = prm.get(f'{first}.allow_unknown', True)
        for plugin in self.plugin_ids:
            prm.get(f'{plugin}.plugin', 'nav2_navfn_planner/NavfnPlanner')
            prm.get(f'{plugin}.use_astar', False)
        result_timeout = prm.get('action_server_result_timeout', RESULT_TIMEOUT_S)
        prm.report_unused()
        self.costmap = CostmapNode('global_costmap', default_frame='map', rolling=False, tf_buffer=self.tf_buffer,
                                   on_update=self._costmap_updated)
        self.planner = GridPlanner(self.costmap.costmap, tolerance=self.tolerance, allow_unknown=self.allow_unknown)
        self.plan_pub = self.create_lifecycle_publisher(Path, 'plan', 1)
        self.goals = GoalRunner(self)
        gated_action_server(self, ComputePathToPose, 'compute_path_to_pose', self._to_pose,
                            result_timeout=result_timeout)
        gated_action_server(self, ComputePathThroughPoses, 'compute_path_through_poses', self._through_poses,
                            result_timeout=result_timeout)

    def on_configure(self, state: State) -> TransitionCallbackReturn:
        self.get_logger().info(f'Configuring: planner {", ".join(self.plugin_ids)} (Dijkstra on the global costmap)')
        return TransitionCallbackReturn.SUCCESS

    def _costmap_updated(self) -> None:
        with self.costmap.lock:
            self.planner.invalidate()

    # -- goals -------------------------------------------------------------------------------
    def _to_pose(self, handle: Any) -> Any:
        goal = handle.request
        return self._serve(handle, ComputePathToPose.Result(), goal.start if goal.use_start else None, [goal.goal],
                           goal.planner_id)

    def _through_poses(self, handle: Any) -> Any:
        goal = handle.request
        result = ComputePathThroughPoses.Result()
        if not goal.goals:
            result.error_code, result.error_msg = 309, 'No viapoints given'
            handle.abort()
            return result
        return self._serve(handle, result, goal.start if goal.use_start else None, list(goal.goals), goal.planner_id,
                           code_offset=100)

    def _serve(self, handle: Any, result: Any, start: Any, goals: list, planner_id: str, code_offset: int = 0) -> Any:
        started = time.monotonic()
        if planner_id and planner_id not in self.plugin_ids:
            return self.goals.fail(handle, result, 201 + code_offset, f'planner id {planner_id} is invalid')
        deadline = time.monotonic() + _MAP_WAIT_S
        while not self.costmap.ready and time.monotonic() < deadline:
            time.sleep(0.05)
        if not self.costmap.ready:
            return self.goals.fail(handle, result, UNKNOWN + code_offset,
                              'The global costmap has no map yet (nothing received on /map)')
        frame = self.costmap.global_frame
        try:
            if start is None:
                sx, sy, _ = self.costmap.robot_pose()
            else:
                sx, sy, _ = pose_in_frame(self.tf_buffer, start, frame)
            targets = [pose_in_frame(self.tf_buffer, g, frame) for g in goals]
        except Exception as exc:  # noqa: BLE001 - tf2's exceptions
            return self.goals.fail(handle, result, _TF_ERROR + code_offset, f'Could not transform the poses into {frame}: {exc}')
        pieces = []
        try:
            with self.costmap.lock:
                for gx, gy, _ in targets:
                    piece = self.planner.plan((sx, sy), (gx, gy))
                    pieces.append(piece if not pieces else piece[1:])
                    sx, sy = piece[-1]
        except PlanningError as exc:
            return self.goals.fail(handle, result, exc.code + code_offset, str(exc))
        points = np.concatenate(pieces)
        stamp = self.get_clock().now().to_msg()
        result.path = path_msg(points, path_yaws(points, targets[-1][2]), frame, stamp)
        result.planning_time = duration_msg(time.monotonic() - started)
        self.plan_pub.publish(result.path)
        elapsed = time.monotonic() - started
        if self.expected_frequency > 0 and elapsed > 1.0 / self.expected_frequency:
            self.get_logger().warn(f'Planner loop missed its desired rate of {self.expected_frequency:.4f} Hz. '
                                   f'Current loop rate is {1.0 / elapsed:.4f} Hz', throttle_duration_sec=10.0)
        handle.succeed()
        return result


def main(args: list[str] | None = None) -> int:
    try:
        with zros.init(args=args):
            node = PlannerServer()
            spin_nodes(node, node.costmap)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    return 0


if __name__ == '__main__':
    sys.exit(main())
