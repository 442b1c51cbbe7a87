"""turtlebot3_bringup: what runs on the robot (robot.launch.py) and, in zros, its laptop half
(laptop.launch.py), for a TurtleBot3 whose drivers are the simulator (docs/multi-machine.md)."""
