"""ros_gz_sim: Gazebo Sim's ROS package (gz_sim.launch.py, create, the gz command), played by zros's simulator."""
