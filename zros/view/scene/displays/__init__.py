"""The display types of the scene view, by RViz class name and by message type."""
from __future__ import annotations

from zros.view.scene.displays.base import Display, DisplayContext, Status
from zros.view.scene.displays.maps import MapDisplay
from zros.view.scene.displays.markers import MarkerDisplay
from zros.view.scene.displays.poses import (
    OdometryDisplay, PathDisplay, PoseArrayDisplay, PoseDisplay, PoseWithCovarianceDisplay,
)
from zros.view.scene.displays.robot import RobotModelDisplay
from zros.view.scene.displays.sensors import ImageDisplay, LaserScanDisplay, PointCloud2Display
from zros.view.scene.displays.tf import TFDisplay

__all__ = ['Display', 'DisplayContext', 'Status', 'DISPLAY_KINDS', 'display_for_type', 'display_for_topic']

DISPLAY_KINDS: dict[str, type[Display]] = {cls.kind: cls for cls in (
    MapDisplay, LaserScanDisplay, PointCloud2Display, ImageDisplay, PoseDisplay, PoseWithCovarianceDisplay,
    OdometryDisplay, PoseArrayDisplay, PathDisplay, MarkerDisplay, TFDisplay, RobotModelDisplay)}


def display_for_type(msg_type: str) -> type[Display] | None:
    """The display class that draws `msg_type` ('pkg/msg/Name'), or None."""
    for cls in DISPLAY_KINDS.values():
        if msg_type in cls.msg_types:
            return cls
    return None


def display_for_topic(topic: str, msg_type: str) -> type[Display] | None:
    """The display for a topic of the graph: by type, except that only a robot_description
    String is a robot model (a String topic is usually text)."""
    cls = display_for_type(msg_type)
    if cls is RobotModelDisplay and not topic.endswith('robot_description'):
        return None
    return cls
