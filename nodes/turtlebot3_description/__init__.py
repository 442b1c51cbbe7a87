"""turtlebot3_description: the TurtleBot3 burger's URDF (share files under urdf/)."""
