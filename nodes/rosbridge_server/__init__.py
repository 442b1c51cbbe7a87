"""`rosbridge_server`: rosbridge's WebSocket server under ROS's package and executable names, so
`zros run rosbridge_server rosbridge_websocket` and `rosbridge_websocket_launch.xml` give web
pages built on roslib the zros graph (docs/web-tools.md)."""
