"""Actions: long-running goals with feedback, results and cancellation (rclpy.action)."""
from zros.action.client import ActionClient, ClientGoalHandle
from zros.action.server import (ActionServer, CancelResponse, GoalResponse, GoalStatus, ServerGoalHandle,
                                default_cancel_callback, default_goal_callback,
                                default_handle_accepted_callback)

__all__ = ['ActionServer', 'ActionClient', 'ServerGoalHandle', 'ClientGoalHandle', 'GoalResponse',
           'CancelResponse', 'GoalStatus', 'default_goal_callback', 'default_cancel_callback',
           'default_handle_accepted_callback']
