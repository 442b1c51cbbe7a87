"""Actions: long-running goals with feedback, results and cancellation (rclpy.action)."""
from zros.action.client import ActionClient, ClientGoalHandle
from zros.action.graph import (get_action_client_names_and_types_by_node, get_action_names_and_types,
                               get_action_server_names_and_types_by_node)
from zros.action.server import (ActionServer, CancelResponse, GoalResponse, GoalStatus, ServerGoalHandle,
                                default_cancel_callback, default_goal_callback,
                                default_handle_accepted_callback)

__all__ = ['ActionServer', 'ActionClient', 'ServerGoalHandle', 'ClientGoalHandle', 'GoalResponse',
           'CancelResponse', 'GoalStatus', 'default_goal_callback', 'default_cancel_callback',
           'default_handle_accepted_callback', 'get_action_client_names_and_types_by_node',
           'get_action_server_names_and_types_by_node', 'get_action_names_and_types']
