"""nav2_loopback_sim: Nav2 Jazzy's loopback simulator (cmd_vel integrated into odometry and TF, a scan from the map)."""
