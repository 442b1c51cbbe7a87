"""rclpy.clock_type: ClockType (ROS_TIME, SYSTEM_TIME, STEADY_TIME)."""
from zros.time import ClockType

__all__ = ['ClockType']
