"""ros_gz_bridge: parameter_bridge, the relay between Gazebo Sim's topics and ROS's."""
