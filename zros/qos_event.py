"""`rclpy.qos_event`, the module name of the QoS event API up to ROS 2 Humble (Iron renamed it
`event_handler`); Humble-era code imports from here."""
from zros.event_handler import *  # noqa: F401,F403 - the same names, under the old module path
from zros.event_handler import EventHandler, __all__

QoSEventHandler = EventHandler

__all__ = [*__all__, 'QoSEventHandler']
