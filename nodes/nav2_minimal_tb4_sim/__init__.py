"""nav2_minimal_tb4_sim: Nav2 Jazzy's TurtleBot4 in Gazebo Sim (spawn_tb4.launch.py, the depot and warehouse worlds), on zros's simulator."""
