"""`zros.sensor_msgs_py`: ROS 2's sensor_msgs_py helpers (`point_cloud2`) for zros messages."""
