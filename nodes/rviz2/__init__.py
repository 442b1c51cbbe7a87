"""rviz2: the course's `ros2 run rviz2 rviz2 -d config.rviz`, served as the zros scene view in the browser."""
