"""map_server: a map file served on /map, as nav2_map_server's map_server (a lifecycle node).

    zros run nav2_map_server map_server --ros-args -p yaml_filename:=$HOME/map.yaml -p autostart:=true
    zros service call /map_server/load_map nav2_msgs/srv/LoadMap "{map_url: $HOME/other.yaml}"
    zros service call /map_server/map nav_msgs/srv/GetMap

As Nav2's, the node starts unconfigured: a lifecycle manager (navigation2.launch.py's
lifecycle_manager_localization) or `zros lifecycle set /map_server configure` then `activate`
brings it up; `autostart:=true` does both at once (for a map server run by hand).

Parameters: `yaml_filename` (the map's YAML file: a path, `file://` or `package://pkg/...` URL), `topic_name` ("map"), `frame_id` ("map"),
`autostart` (false). configure loads the file and creates the services `map_server/map`
(nav_msgs/GetMap) and `map_server/load_map` (nav2_msgs/srv/LoadMap); activate publishes the map
on `topic_name` (nav_msgs/OccupancyGrid, reliable, transient local, depth 1: a late subscriber
gets it); each successful load_map publishes the new map. The file rules are zros.map_io's.

A bad file at configure is one error line naming the file and key, and configure fails (with
`autostart`, the node exits 1); a failed load_map answers with its result code, logs that
line, and keeps serving the previous map.
"""
from __future__ import annotations

import sys
from pathlib import Path
from typing import Any

import zros
from zros.ament_index_python.packages import get_package_share_path
from zros.executors import ExternalShutdownException
from zros.lifecycle import LifecycleNode, State, TransitionCallbackReturn
from zros.map_io import (MapFileError, MapImageError, MapMetadataError, MapNotFoundError, OccupancyMap, load_map,
                         map_to_msg)
from zros.qos import DurabilityPolicy, QoSProfile

from interfaces.nav2_msgs.srv import LoadMap
from interfaces.nav_msgs.msg import OccupancyGrid
from interfaces.nav_msgs.srv import GetMap

__all__ = ['MapServer', 'MAP_QOS', 'resolve_map_url', 'main']

#: /map's QoS everywhere in zros (nav2 and slam_toolbox use the same): late subscribers get it.
MAP_QOS = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL)
#: [s] unconfigured this long with no manager in sight: say how to bring the node up.
_HINT_AFTER_S = 5.0

_RESULT_FOR = ((MapNotFoundError, 'RESULT_MAP_DOES_NOT_EXIST'), (MapMetadataError, 'RESULT_INVALID_MAP_METADATA'),
               (MapImageError, 'RESULT_INVALID_MAP_DATA'))


def resolve_map_url(url: str) -> Path:
    """A load_map URL as a path: a plain path, `file:///abs/path.yaml`, or
    `package://pkg/rel/path.yaml` (in the package's share directory).

    Raises:
        MapNotFoundError: an unknown package.
    """
    if url.startswith('file://'):
        return Path(url[len('file://'):]).expanduser()
    if url.startswith('package://'):
        package, _, rest = url[len('package://'):].partition('/')
        try:
            return get_package_share_path(package) / rest
        except KeyError as exc:
            raise MapNotFoundError(f'{url}: {exc}') from None
    return Path(url).expanduser()


class MapServer(LifecycleNode):
    """Loads the map at configure, publishes it at activate, answers GetMap and LoadMap."""

    def __init__(self, **kwargs: Any) -> None:
        super().__init__('map_server', **kwargs)
        self.declare_parameter('yaml_filename', '')
        self.declare_parameter('topic_name', 'map')
        self.declare_parameter('frame_id', 'map')
        self.declare_parameter('autostart', False)
        self._msg: Any = None
        self._publisher: Any = None
        self._services: list[Any] = []
        self._hint = self.create_timer(_HINT_AFTER_S, self._hint_once)

    def _hint_once(self) -> None:
        self.destroy_timer(self._hint)
        if self.current_state.label == 'unconfigured':
            self.get_logger().info(f'{self.get_fully_qualified_name()} is unconfigured, waiting for a lifecycle '
                                   f'manager: `zros lifecycle set {self.get_fully_qualified_name()} configure`, '
                                   'then `activate` (or run it with -p autostart:=true)')

    # -- lifecycle ------------------------------------------------------------------------------
    def on_configure(self, state: State) -> TransitionCallbackReturn:
        filename = str(self.get_parameter('yaml_filename').value)
        if not filename:
            self.get_logger().error('yaml_filename is empty: set it to the map\'s YAML file')
            return TransitionCallbackReturn.FAILURE
        try:
            self._msg = self._message(load_map(resolve_map_url(filename)))
        except MapFileError as exc:
            self.get_logger().error(str(exc))
            return TransitionCallbackReturn.FAILURE
        self._log_loaded(filename)
        self._publisher = self.create_lifecycle_publisher(OccupancyGrid, str(self.get_parameter('topic_name').value),
                                                          MAP_QOS)
        self._services = [self.create_service(GetMap, '~/map', self._on_get_map),
                          self.create_service(LoadMap, '~/load_map', self._on_load_map)]
        return TransitionCallbackReturn.SUCCESS

    def on_activate(self, state: State) -> TransitionCallbackReturn:
        result = super().on_activate(state)
        if result == TransitionCallbackReturn.SUCCESS:
            self._publisher.publish(self._msg)
        return result

    def on_cleanup(self, state: State) -> TransitionCallbackReturn:
        for service in self._services:
            self.destroy_service(service)
        if self._publisher is not None:
            self.destroy_lifecycle_publisher(self._publisher)
        self._services, self._publisher, self._msg = [], None, None
        return TransitionCallbackReturn.SUCCESS

    def on_shutdown(self, state: State) -> TransitionCallbackReturn:
        return TransitionCallbackReturn.SUCCESS

    # -- the map --------------------------------------------------------------------------------
    def _message(self, grid: OccupancyMap) -> Any:
        return map_to_msg(grid, frame_id=str(self.get_parameter('frame_id').value),
                          stamp=self.get_clock().now().to_msg())

    def _log_loaded(self, filename: str) -> None:
        info = self._msg.info
        self.get_logger().info(f'Loaded {filename}: {info.width} X {info.height} map @ {info.resolution:.3f} m/cell')

    def _on_get_map(self, request: Any, response: Any) -> Any:
        response.map = self._msg
        return response

    def _on_load_map(self, request: Any, response: Any) -> Any:
        url = request.map_url
        try:
            grid = load_map(resolve_map_url(url))
        except MapFileError as exc:
            self.get_logger().error(f'load_map failed, keeping the previous map: {exc}')
            response.result = next(getattr(response, code) for kind, code in _RESULT_FOR if isinstance(exc, kind))
            return response
        self._msg = self._message(grid)
        self._log_loaded(url)
        self._publisher.publish(self._msg)
        response.map = self._msg
        response.result = response.RESULT_SUCCESS
        return response


def main(args: list[str] | None = None) -> int:
    try:
        with zros.init(args=args):
            node = MapServer()
            if node.get_parameter('autostart').value:
                if node.trigger_configure() != TransitionCallbackReturn.SUCCESS:
                    return 1                      # the error line is logged
                node.trigger_activate()
            zros.spin(node)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    return 0


if __name__ == '__main__':
    sys.exit(main())
