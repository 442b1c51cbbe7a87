"""`demo_nodes_py talker`: demo_nodes' talker under the ROS 2 package name."""
from nodes.demo_nodes.talker import main

__all__ = ['main']
