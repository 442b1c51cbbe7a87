"""turtlesim: ROS 2's first simulated robot on zros (pymunk physics, a canvas published as an image)."""
