"""`demo_nodes_cpp add_two_ints_client`: demo_nodes' add_two_ints_client under the ROS 2 package name."""
from nodes.demo_nodes.add_two_ints_client import main

__all__ = ['main']
