"""map_saver_server: Nav2's map saver as a service (a lifecycle node, as nav2_bringup's
slam_launch.py starts it next to SLAM).

    zros run nav2_map_server map_saver_server --ros-args -p autostart:=true
    zros service call /map_saver/save_map nav2_msgs/srv/SaveMap "{map_url: /tmp/map, map_topic: map}"

Once active it serves `map_saver/save_map` (nav2_msgs/srv/SaveMap): it takes one map from
`map_topic` (default `map`), waiting up to `save_map_timeout` seconds, and writes `map_url`.yaml
and the image by zros.map_io's rules, as map_saver_cli does. Empty request fields take the
defaults: format pgm, mode trinary, thresholds from `free_thresh_default` (0.196, see
docs/slam.md) and `occupied_thresh_default` (0.65). Parameters as Nav2's, plus `autostart`.
"""
from __future__ import annotations

import sys
from typing import Any

import zros
from zros.callback_groups import ReentrantCallbackGroup
from zros.executors import ExternalShutdownException, spin_nodes
from zros.lifecycle import LifecycleNode, State, TransitionCallbackReturn
from zros.map_io import DEFAULT_FREE_THRESH, DEFAULT_OCCUPIED_THRESH

from interfaces.nav2_msgs.srv import SaveMap
from nodes.nav2_map_server._saver import DEFAULT_TIMEOUT, save_map_from_topic

__all__ = ['MapSaverServer', 'main']


class MapSaverServer(LifecycleNode):
    """The save_map service, created at configure and answered while active."""

    def __init__(self, **kwargs: Any) -> None:
        super().__init__('map_saver', **kwargs)
        self.declare_parameter('save_map_timeout', DEFAULT_TIMEOUT)
        self.declare_parameter('free_thresh_default', DEFAULT_FREE_THRESH)
        self.declare_parameter('occupied_thresh_default', DEFAULT_OCCUPIED_THRESH)
        self.declare_parameter('map_subscribe_transient_local', True)
        self.declare_parameter('autostart', False)
        self._service: Any = None

    def on_configure(self, state: State) -> TransitionCallbackReturn:
        self._service = self.create_service(SaveMap, '~/save_map', self._on_save_map,
                                            callback_group=ReentrantCallbackGroup())
        return TransitionCallbackReturn.SUCCESS

    def on_cleanup(self, state: State) -> TransitionCallbackReturn:
        if self._service is not None:
            self.destroy_service(self._service)
            self._service = None
        return TransitionCallbackReturn.SUCCESS

    def on_shutdown(self, state: State) -> TransitionCallbackReturn:
        return TransitionCallbackReturn.SUCCESS

    def _on_save_map(self, request: Any, response: Any) -> Any:
        if self.current_state.label != 'active':
            self.get_logger().warn('save_map: the map saver is not active (configure and activate it first)')
            response.result = False
            return response
        free = request.free_thresh or float(self.get_parameter('free_thresh_default').value)
        occupied = request.occupied_thresh or float(self.get_parameter('occupied_thresh_default').value)
        response.result = save_map_from_topic(
            self, request.map_topic or 'map', request.map_url or 'map',
            timeout=float(self.get_parameter('save_map_timeout').value),
            transient_local=bool(self.get_parameter('map_subscribe_transient_local').value),
            mode=request.map_mode or 'trinary', image_format=request.image_format or None,
            free_thresh=free, occupied_thresh=occupied)
        return response


def main(args: list[str] | None = None) -> int:
    try:
        with zros.init(args=args):
            node = MapSaverServer()
            if node.get_parameter('autostart').value:
                node.trigger_configure()
                node.trigger_activate()
            spin_nodes(node)        # the service waits for a map on another thread
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    return 0


if __name__ == '__main__':
    sys.exit(main())
