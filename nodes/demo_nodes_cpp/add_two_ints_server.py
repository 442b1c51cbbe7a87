"""`demo_nodes_cpp add_two_ints_server`: demo_nodes' add_two_ints_server under the ROS 2 package name."""
from nodes.demo_nodes.add_two_ints_server import main

__all__ = ['main']
