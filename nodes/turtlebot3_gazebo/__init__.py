"""turtlebot3_gazebo: the simulated TurtleBot3 worlds (Gazebo's role, on zros.sim)."""
