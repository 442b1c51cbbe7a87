"""`zros.impl`: the module paths rclpy code imports from `rclpy.impl` (rcutils' logging names)."""
