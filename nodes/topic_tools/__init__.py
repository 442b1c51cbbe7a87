"""topic_tools: relay, throttle and drop any topic, by ROS 2's package name (ros-tooling/topic_tools).

The tools copy serialized messages without decoding them; the type and QoS come from the
topic's publishers in the graph (`_tool_base.ToolNode`), and the decisions from `_filters`.
"""
