"""`cartographer_ros`: Cartographer's two nodes by their ROS names, as turtlebot3_cartographer's
launch files start them, with zros's SLAM (docs/slam.md) doing the mapping:

- `cartographer_node -configuration_directory DIR -configuration_basename FILE.lua`: the Lua
  configuration is read (zros.slam.cartographer_lua) for frames, range limits and timeouts; the
  node publishes map -> odom and serves its map as `cartographer_node/dynamic_map`, and, as
  Cartographer's, does not publish /map itself.
- `cartographer_occupancy_grid_node -resolution R -publish_period_sec P`: publishes /map every P
  seconds, at R metres a cell, from cartographer_node's map.
"""
