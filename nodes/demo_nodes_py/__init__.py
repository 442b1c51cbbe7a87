"""`demo_nodes_py`: the name ROS 2's Python demo package has, so `zros run demo_nodes_py talker` (the first
command of many courses) runs zros's demo nodes. Each executable here is the `demo_nodes` one."""
