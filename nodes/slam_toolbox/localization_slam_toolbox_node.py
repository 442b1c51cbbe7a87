"""localization_slam_toolbox_node: slam_toolbox's localization mode, on zros's SLAM.

    zros launch slam_toolbox localization_launch.py     # map_file_name, map_start_pose in its params file
    zros topic pub --once /initialpose geometry_msgs/msg/PoseWithCovarianceStamped \
        "{header: {frame_id: map}, pose: {pose: {position: {x: 1.0, y: 0.5}}}}"

The async node (async_slam_toolbox_node) with the map kept fixed: a serialized pose graph
(`map_file_name` at `map_start_pose`, or `deserialize_map` with LOCALIZE_AT_POSE) is loaded,
published on /map, and each scan is matched against its keyframes nearest the robot plus a
rolling buffer of the last `scan_buffer_size` localized scans, which are never added to the map
(zros.slam.mapper). Out: map -> odom, and `pose`. `/initialpose` (as RViz's "2D Pose Estimate"
sends) relocalizes: the next scan is searched around it. `~/clear_localization_buffer`
(std_srvs/Empty) empties the buffer. As in slam_toolbox, `serialize_map` and `save_map` are not
offered in this mode (serialize_map answers with an error).
"""
from __future__ import annotations

import sys
from typing import Any

from zros.rotations import yaw_from_quaternion

from interfaces.geometry_msgs.msg import PoseWithCovarianceStamped
from interfaces.slam_toolbox.srv import DeserializePoseGraph
from interfaces.std_srvs.srv import Empty
from nodes.slam_toolbox.async_slam_toolbox_node import SlamNode
from nodes.slam_toolbox.async_slam_toolbox_node import main as slam_main

__all__ = ['LocalizationNode', 'main']


class LocalizationNode(SlamNode):
    """SlamNode localizing in a fixed loaded map (module docstring)."""

    LOCALIZING = True
    MATCH_TYPES = {DeserializePoseGraph.Request.LOCALIZE_AT_POSE: 'LOCALIZE_AT_POSE'}

    def _create_mode_entities(self, keep: Any) -> None:
        keep(self.create_subscription(PoseWithCovarianceStamped, 'initialpose', self._on_initial_pose, 1))
        keep(self.create_service(Empty, '~/clear_localization_buffer', self._on_clear_buffer))

    def _process(self, msg: Any) -> None:
        if not self._slam.localizing:           # nothing to localize in: scans wait for a map
            self._warn_once('no map', 'no map to localize in: set map_file_name and map_start_pose, or call '
                                      'deserialize_map with match_type 3 (LOCALIZE_AT_POSE); scans are ignored')
            return
        super()._process(msg)

    def _on_serialize(self, request: Any, response: Any) -> Any:
        self.get_logger().error('serialize_map: cannot serialize the map in localization mode')
        response.result = response.RESULT_UNDEFINED_FAILURE
        return response

    def _on_initial_pose(self, msg: PoseWithCovarianceStamped) -> None:
        p, q = msg.pose.pose.position, msg.pose.pose.orientation
        pose = (float(p.x), float(p.y), yaw_from_quaternion(q.x, q.y, q.z, q.w))
        with self._lock:
            self._slam.relocalize(pose)
        self.get_logger().info(f'Localizing to ({pose[0]:.2f}, {pose[1]:.2f}), theta={pose[2]:.2f}')

    def _on_clear_buffer(self, request: Any, response: Any) -> Any:
        with self._lock:
            self._slam.clear_localization_buffer()
        self.get_logger().info('Localization buffer cleared')
        return response


def main(args: list[str] | None = None) -> int:
    return slam_main(args, node_class=LocalizationNode)


if __name__ == '__main__':
    sys.exit(main())
