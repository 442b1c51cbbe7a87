"""turtlebot3_teleop: keyboard teleoperation for the TurtleBot3 (turtlebot3_teleop's role)."""
