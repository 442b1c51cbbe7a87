"""`rclcpp_components component_container_isolated`: the same empty container as `component_container`."""
from nodes.rclcpp_components.component_container import main

__all__ = ['main']
