"""`demo_nodes_py listener`: demo_nodes' listener under the ROS 2 package name."""
from nodes.demo_nodes.listener import main

__all__ = ['main']
