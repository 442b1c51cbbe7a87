"""LifecycleNode: a node with ROS 2's managed life cycle (rclpy.lifecycle's API).

It starts `unconfigured`. The transitions run its `on_configure`, `on_activate`,
`on_deactivate`, `on_cleanup`, `on_shutdown` and `on_error` methods (override them; the
defaults drive the node's managed entities, such as lifecycle publishers). It serves
`<node>/get_state`, `<node>/change_state`, `<node>/get_available_states`,
`<node>/get_available_transitions` and `<node>/get_transition_graph`, and publishes each step
on `<node>/transition_event`, with ROS's ids and lower-case labels.

A callback that raises, or returns something other than a TransitionCallbackReturn, counts
as ERROR (the node then runs on_error) and the reason is logged; rclpy would crash the
service or log nothing.
"""
from __future__ import annotations

import threading
import time
from typing import TYPE_CHECKING, Any

from zros.lifecycle.managed_entity import ManagedEntity
from zros.lifecycle.publisher import LifecyclePublisher
from zros.lifecycle.state_machine import (ERRORPROCESSING, PUBLIC_TRANSITIONS, RESULT_TRANSITIONS, STATES,
                                          LifecycleState, LifecycleStateMachine, TransitionCallbackReturn,
                                          TransitionDescription, TransitionError)
from zros.node import Node

__all__ = ['LifecycleNode', 'LifecycleNodeMixin']

# The mixin is only ever mixed into a Node (LifecycleNode, or a user's class that derives from
# Node): the checker is told so, while at run time the Node comes from the class that mixes it in.
if TYPE_CHECKING:
    _MixedIntoNode = Node
else:
    _MixedIntoNode = object

_CALLBACKS = {'configuring': 'on_configure', 'cleaningup': 'on_cleanup', 'shuttingdown': 'on_shutdown',
              'activating': 'on_activate', 'deactivating': 'on_deactivate', 'errorprocessing': 'on_error'}


class LifecycleNodeMixin(ManagedEntity, _MixedIntoNode):
    """The lifecycle part of LifecycleNode, for classes that already derive from Node."""

    def __init__(self, *, enable_communication_interface: bool = True, callback_group: Any = None) -> None:
        from interfaces.lifecycle_msgs.msg import TransitionEvent
        from interfaces.lifecycle_msgs.srv import ChangeState, GetAvailableStates, GetAvailableTransitions, GetState
        self._state_machine = LifecycleStateMachine()
        self._transition_lock = threading.Lock()
        self._managed_entities: set[ManagedEntity] = set()
        self._transition_event_pub = None
        if enable_communication_interface:
            group = callback_group or self.default_callback_group
            self._transition_event_pub = self.create_publisher(TransitionEvent, '~/transition_event', 10)
            self.create_service(ChangeState, '~/change_state', self._on_change_state, callback_group=group)
            self.create_service(GetState, '~/get_state', self._on_get_state, callback_group=group)
            self.create_service(GetAvailableStates, '~/get_available_states', self._on_get_available_states,
                                callback_group=group)
            self.create_service(GetAvailableTransitions, '~/get_available_transitions',
                                self._on_get_available_transitions, callback_group=group)
            self.create_service(GetAvailableTransitions, '~/get_transition_graph', self._on_get_transition_graph,
                                callback_group=group)

    # -- state ---------------------------------------------------------------------------------
    @property
    def current_state(self) -> LifecycleState:
        """The state the node is in now (a LifecycleState with `state_id` and `label`)."""
        return self._state_machine.current

    def trigger_configure(self) -> TransitionCallbackReturn:
        """Run the configure transition (unconfigured to inactive), calling `on_configure`.

        :return: What the callback returned (ERROR if it raised).
        :raises TransitionError: If the node is not unconfigured, or another transition runs.
        """
        return self._change_state('configure')

    def trigger_cleanup(self) -> TransitionCallbackReturn:
        """Run the cleanup transition (inactive to unconfigured), calling `on_cleanup`.

        :return: What the callback returned (ERROR if it raised).
        :raises TransitionError: If the node is not inactive, or another transition runs.
        """
        return self._change_state('cleanup')

    def trigger_activate(self) -> TransitionCallbackReturn:
        """Run the activate transition (inactive to active), calling `on_activate`.

        :return: What the callback returned (ERROR if it raised).
        :raises TransitionError: If the node is not inactive, or another transition runs.
        """
        return self._change_state('activate')

    def trigger_deactivate(self) -> TransitionCallbackReturn:
        """Run the deactivate transition (active to inactive), calling `on_deactivate`.

        :return: What the callback returned (ERROR if it raised).
        :raises TransitionError: If the node is not active, or another transition runs.
        """
        return self._change_state('deactivate')

    def trigger_shutdown(self) -> TransitionCallbackReturn:
        """Run the shutdown transition from any primary state but finalized, calling `on_shutdown`.

        :return: What the callback returned (ERROR if it raised).
        :raises TransitionError: If the node is finalized, or another transition runs.
        """
        return self._change_state('shutdown')

    def _change_state(self, transition: int | str) -> TransitionCallbackReturn:
        """Run one public transition to its end. Raises TransitionError when the current state
        does not offer it, or another transition is under way."""
        if not self._transition_lock.acquire(blocking=False):
            raise TransitionError(f"a transition of '{self.get_name()}' is already under way "
                                  f"(state '{self._state_machine.current.label}')")
        try:
            machine = self._state_machine
            start = machine.current
            self._publish_event(machine.begin(transition))
            result = self._run_callback(machine.current, start)
            self._publish_event(machine.finish(result))
            if machine.current == ERRORPROCESSING:
                self._publish_event(machine.finish(self._run_callback(ERRORPROCESSING, start)))
            return result
        finally:
            self._transition_lock.release()

    def _run_callback(self, state: LifecycleState, previous: LifecycleState) -> TransitionCallbackReturn:
        name = _CALLBACKS[state.label]
        try:
            result = getattr(self, name)(previous)
        except Exception as exc:  # noqa: BLE001 - a failing callback is the ERROR outcome, not a crash
            self.get_logger().error(f'{name}() raised {type(exc).__name__}: {exc}')
            return TransitionCallbackReturn.ERROR
        if not isinstance(result, TransitionCallbackReturn):
            self.get_logger().error(f'{name}() returned {result!r}; it must return a TransitionCallbackReturn '
                                    '(SUCCESS, FAILURE or ERROR)')
            return TransitionCallbackReturn.ERROR
        return result

    def _publish_event(self, transition: TransitionDescription) -> None:
        if self._transition_event_pub is None:
            return
        from interfaces.lifecycle_msgs.msg import TransitionEvent
        event = TransitionEvent(timestamp=time.time_ns())
        _fill_description(event, transition)
        self._transition_event_pub.publish(event)

    # -- managed entities ----------------------------------------------------------------------
    def add_managed_entity(self, entity: ManagedEntity) -> None:
        """Have the default transition callbacks drive `entity` too.

        :param entity: A ManagedEntity (a lifecycle publisher, or one of your own).
        :raises TypeError: If `entity` is not a ManagedEntity.
        """
        if not isinstance(entity, ManagedEntity):
            raise TypeError('Expected a zros.lifecycle.ManagedEntity instance.')
        self._managed_entities.add(entity)

    def _for_entities(self, name: str, state: LifecycleState) -> TransitionCallbackReturn:
        for entity in list(self._managed_entities):
            result = getattr(entity, name)(state)
            if result != TransitionCallbackReturn.SUCCESS:
                return result
        return TransitionCallbackReturn.SUCCESS

    def on_configure(self, state: LifecycleState) -> TransitionCallbackReturn:
        """Override to load parameters and create entities; by default configures the managed entities.

        :param state: The state the transition started from.
        :return: SUCCESS (to inactive), FAILURE (stay unconfigured) or ERROR (to on_error).
        """
        return self._for_entities('on_configure', state)

    def on_cleanup(self, state: LifecycleState) -> TransitionCallbackReturn:
        """Override to release what on_configure made; by default cleans up the managed entities.

        :param state: The state the transition started from.
        :return: SUCCESS (to unconfigured), FAILURE or ERROR.
        """
        return self._for_entities('on_cleanup', state)

    def on_shutdown(self, state: LifecycleState) -> TransitionCallbackReturn:
        """Override to release everything before the node is finalized; by default shuts the managed
        entities down.

        :param state: The state the transition started from.
        :return: SUCCESS (to finalized), FAILURE or ERROR.
        """
        return self._for_entities('on_shutdown', state)

    def on_activate(self, state: LifecycleState) -> TransitionCallbackReturn:
        """Override to start work; by default activates the managed entities (publishers start sending).

        :param state: The state the transition started from.
        :return: SUCCESS (to active), FAILURE (stay inactive) or ERROR.
        """
        return self._for_entities('on_activate', state)

    def on_deactivate(self, state: LifecycleState) -> TransitionCallbackReturn:
        """Override to pause work; by default deactivates the managed entities.

        :param state: The state the transition started from.
        :return: SUCCESS (to inactive), FAILURE (stay active) or ERROR.
        """
        return self._for_entities('on_deactivate', state)

    def on_error(self, state: LifecycleState) -> TransitionCallbackReturn:
        """Override to recover after a callback returned ERROR or raised; by default asks the managed
        entities.

        :param state: The state the failed transition started from.
        :return: SUCCESS (back to unconfigured) or anything else (to finalized).
        """
        return self._for_entities('on_error', state)

    def create_lifecycle_publisher(self, *args: Any, **kwargs: Any) -> LifecyclePublisher:
        """create_publisher's arguments; the publisher only publishes while the node is active."""
        if 'publisher_class' in kwargs:
            raise TypeError("create_lifecycle_publisher() got an unexpected keyword argument 'publisher_class'")
        publisher: Any = Node.create_publisher(self, *args, **kwargs, publisher_class=LifecyclePublisher)
        if self._state_machine.current.label == 'active':
            publisher.on_activate(self._state_machine.current)
        self._managed_entities.add(publisher)
        return publisher

    def destroy_lifecycle_publisher(self, publisher: LifecyclePublisher) -> bool:
        """Destroy a publisher made by `create_lifecycle_publisher`.

        :param publisher: The lifecycle publisher.
        :return: ``True`` if the node had it.
        """
        self._managed_entities.discard(publisher)
        return Node.destroy_publisher(self, publisher)

    # -- services --------------------------------------------------------------------------------
    def _on_change_state(self, request: Any, response: Any) -> Any:
        transition = request.transition.label or request.transition.id
        try:
            response.success = self._change_state(transition) == TransitionCallbackReturn.SUCCESS
        except TransitionError as exc:
            self.get_logger().warn(f'change_state refused: {exc}')
            response.success = False
        return response

    def _on_get_state(self, request: Any, response: Any) -> Any:
        state = self._state_machine.current
        response.current_state.id, response.current_state.label = state.state_id, state.label
        return response

    def _on_get_available_states(self, request: Any, response: Any) -> Any:
        from interfaces.lifecycle_msgs.msg import State
        response.available_states = [State(id=s.state_id, label=s.label) for s in STATES]
        return response

    def _on_get_available_transitions(self, request: Any, response: Any) -> Any:
        response.available_transitions = [_description(t) for t in self._state_machine.available_transitions()]
        return response

    def _on_get_transition_graph(self, request: Any, response: Any) -> Any:
        response.available_transitions = [_description(t) for t in PUBLIC_TRANSITIONS + RESULT_TRANSITIONS]
        return response


def _fill_description(msg: Any, transition: TransitionDescription) -> Any:
    msg.transition.id, msg.transition.label = transition.transition_id, transition.label
    msg.start_state.id, msg.start_state.label = transition.start.state_id, transition.start.label
    msg.goal_state.id, msg.goal_state.label = transition.goal.state_id, transition.goal.label
    return msg


def _description(transition: TransitionDescription) -> Any:
    from interfaces.lifecycle_msgs.msg import TransitionDescription as Description
    return _fill_description(Description(), transition)


class LifecycleNode(LifecycleNodeMixin, Node):
    """A ROS 2 managed node: Node plus the lifecycle state machine and its services."""

    def __init__(self, node_name: str, *, enable_communication_interface: bool = True, **kwargs: Any) -> None:
        Node.__init__(self, node_name, **kwargs)
        LifecycleNodeMixin.__init__(self, enable_communication_interface=enable_communication_interface)
