"""nav2_minimal_tb4_description: the TurtleBot4 (Create 3 base, RPLIDAR A1) as Nav2 Jazzy's TurtleBot4 simulation describes it, for robot_state_publisher and Gazebo Sim (zros's simulator)."""
