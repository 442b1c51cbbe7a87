"""nav2_simple_commander: BasicNavigator and TaskResult (zros.nav2_simple_commander.robot_navigator)."""
