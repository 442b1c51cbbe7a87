"""The protocol types of an action, derived from its Goal/Result/Feedback (docs/protocol.md).

For an action `pkg/action/Name` zros uses three services and these topics:

    <name>/_action/send_goal     Name_SendGoal:   {goal_id, goal, client_id} -> {accepted, goal_id, stamp}
    <name>/_action/cancel_goal   action_msgs/srv/CancelGoal
    <name>/_action/get_result    Name_GetResult:  {goal_id} -> {status, result}   (answered when done)
    <name>/_action/feedback/c<client_id>   Name_FeedbackMessage {goal_id, feedback}, one topic per client
    <name>/_action/feedback      the same, for goals sent without a client id (ROS 2's one topic)
    <name>/_action/status        action_msgs/msg/GoalStatusArray (transient local)

A zero goal id asks the server to pick one (UUID4). The classes are built on first use and
cached on the action class, so importing an action type costs nothing extra; rclpy code reaches
them as `Name.Impl.SendGoalService` and so on, which is why this sits beside the message
classes rather than in zros.action.
"""
from __future__ import annotations

import hashlib
import threading
from typing import Any

from zros.idl import Field, FieldType, MessageSpec, ServiceSpec
from zros.message import make_message_class, make_service_class

__all__ = ['protocol_types', 'ActionTypes', 'ImplAttribute']

_lock = threading.Lock()


class ActionTypes:
    """The protocol classes of one action, under the names rclpy's generated `Name.Impl` uses."""

    def __init__(self, send_goal: type, get_result: type, feedback_message: type, cancel_goal: type,
                 status_message: type) -> None:
        self.SendGoalService = send_goal
        self.GetResultService = get_result
        self.FeedbackMessage = feedback_message
        self.CancelGoalService = cancel_goal
        self.GoalStatusMessage = status_message


class ImplAttribute:
    """`Name.Impl` on an action class: its ActionTypes, built on first access."""

    def __get__(self, instance: Any, owner: type) -> ActionTypes:
        return protocol_types(owner)


def _spec(full_name: str, fields: list[tuple[str, str]]) -> MessageSpec:
    text = ''.join(f'{base} {name}\n' for name, base in fields)
    return MessageSpec(full_name, tuple(Field(name, FieldType(base)) for name, base in fields), (), text,
                       '<zros action protocol>')


def protocol_types(action_type: Any) -> ActionTypes:
    """The protocol classes of `action_type`, built once and cached on the class.

    :param action_type: A generated action class (it has Goal, Result, Feedback).
    :return: Its ActionTypes.
    """
    types = action_type.__dict__.get('_PROTOCOL')
    if types is not None:
        return types
    with _lock:
        types = action_type.__dict__.get('_PROTOCOL')
        if types is None:
            types = _build(action_type)
            action_type._PROTOCOL = types
    return types


def _build(action_type: Any) -> ActionTypes:
    from zros.typesupport import get_message, get_service
    base = action_type._TYPE
    known = {f'{base}_Goal': action_type.Goal, f'{base}_Result': action_type.Result,
             f'{base}_Feedback': action_type.Feedback}

    def resolve(name: str) -> type:
        return known.get(name) or get_message(name)

    uuid, time = 'unique_identifier_msgs/msg/UUID', 'builtin_interfaces/msg/Time'

    def service(suffix: str, request: list, response: list) -> type:
        req = make_message_class(_spec(f'{base}_{suffix}_Request', request), resolve)
        resp = make_message_class(_spec(f'{base}_{suffix}_Response', response), resolve)
        spec = ServiceSpec(f'{base}_{suffix}', req._SPEC, resp._SPEC, req._SPEC.text + '---\n' + resp._SPEC.text)
        cls = make_service_class(spec, req, resp)
        cls._HASH = hashlib.sha256(f'{action_type._HASH};{suffix}'.encode()).hexdigest()[:16]
        return cls

    return ActionTypes(
        send_goal=service('SendGoal', [('goal_id', uuid), ('goal', f'{base}_Goal'), ('client_id', 'string')],
                          [('accepted', 'bool'), ('goal_id', uuid), ('stamp', time)]),
        get_result=service('GetResult', [('goal_id', uuid)], [('status', 'int8'), ('result', f'{base}_Result')]),
        feedback_message=make_message_class(
            _spec(f'{base}_FeedbackMessage', [('goal_id', uuid), ('feedback', f'{base}_Feedback')]), resolve),
        cancel_goal=get_service('action_msgs/srv/CancelGoal'),
        status_message=get_message('action_msgs/msg/GoalStatusArray'),
    )
