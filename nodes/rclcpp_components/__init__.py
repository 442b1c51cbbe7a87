"""`rclcpp_components`: the component containers ROS 2 launch files start by name
(`Node(package='rclcpp_components', executable='component_container_isolated', name='nav2_container')`,
as Nav2's bringup does with `use_composition:=True`).

zros has no shared-library components: every composable node a launch file loads
(`LoadComposableNodes`, `ComposableNodeContainer`) runs as its own process, started by the launch
itself. A container started as a plain node is therefore an empty node of the container's name,
so the graph shows it as ROS's would; it loads nothing.
"""
