"""`rosapi`: rosbridge_suite's rosapi node under its ROS names, the graph and parameters as
/rosapi services for web clients (zros.bridges.rosapi; docs/web-tools.md)."""
