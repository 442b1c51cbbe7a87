"""`demo_nodes_cpp`: the name ROS 2's C++ demo package has, so `zros run demo_nodes_cpp talker` (the first
command of many courses) runs zros's demo nodes. Each executable here is the `demo_nodes` one."""
