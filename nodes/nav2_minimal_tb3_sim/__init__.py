"""nav2_minimal_tb3_sim: Nav2 Jazzy's TurtleBot3 waffle in Gazebo Sim (spawn_tb3.launch.py, the sandbox world), on zros's simulator."""
