"""gazebo_ros: Gazebo's ROS package (gzserver, gzclient, spawn_entity.py), played by zros's simulator."""
