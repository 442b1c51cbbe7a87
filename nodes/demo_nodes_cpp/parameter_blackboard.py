"""`demo_nodes_cpp parameter_blackboard`: demo_nodes' parameter_blackboard under the ROS 2 package name."""
from nodes.demo_nodes.parameter_blackboard import main

__all__ = ['main']
