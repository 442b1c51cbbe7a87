"""launch_ros.actions.lifecycle_transition: `LifecycleTransition`, a sequence of lifecycle
transitions for the lifecycle nodes of given names, built from zros.launch's lifecycle events.

For each node the first transition is asked for at once (a ChangeState event aimed by
`matches_node_name`); each later one when the node reports the goal state of the one before
(an OnStateTransition handler), so the sequence must be one the node can go through.
"""
from __future__ import annotations

from typing import Any, Iterable

from zros.launch.action import Action
from zros.launch.actions.events import RegisterEventHandler
from zros.launch.actions.shutdown import EmitEvent
from zros.launch.lifecycle import ChangeState, OnStateTransition, StateTransition
from zros.launch_ros.events.matchers import matches_node_name
from zros.launch_ros.utilities.namespace_utils import make_namespace_absolute

__all__ = ['LifecycleTransition']

#: lifecycle_msgs/Transition id -> (start_state, goal_state) of the step that completes it
TRANSITION_STATES = {
    1: ('configuring', 'inactive'),
    2: ('cleaningup', 'unconfigured'),
    3: ('activating', 'active'),
    4: ('deactivating', 'inactive'),
    5: ('shuttingdown', 'finalized'),
    6: ('shuttingdown', 'finalized'),
    7: ('shuttingdown', 'finalized'),
}


class LifecycleTransition(Action):
    """`LifecycleTransition(lifecycle_node_names=[...], transition_ids=[...])`: take each named
    lifecycle node through the transitions, in order (ids as ints or substitutions).

    Raises:
        ValueError: no node names or no transitions.
    """

    def __init__(self, *, lifecycle_node_names: Iterable[Any], transition_ids: Iterable[Any], **kwargs: Any) -> None:
        super().__init__(**kwargs)
        names, ids = list(lifecycle_node_names), list(transition_ids)
        if not ids:
            raise ValueError('No transition_ids provided.')
        if not names:
            raise ValueError('No lifecycle_node_names provided.')
        self.lifecycle_node_names = [self._text(name, 'lifecycle_node_names') for name in names]
        self.transition_ids = [self._text(str(tid) if isinstance(tid, int) else tid, 'transition_ids') for tid in ids]

    def _ids(self, context: Any) -> list[int]:
        ids = []
        for text in self.transition_ids:
            value = text.perform(context)
            try:
                ids.append(int(value))
            except ValueError:
                raise ValueError(f'expected integer for lifecycle transition, got {value}') from None
            if ids[-1] not in TRANSITION_STATES:
                raise ValueError(f'unknown lifecycle transition id {ids[-1]}')
        return ids

    def execute(self, context: Any) -> list[Action]:
        """The handlers that chain the later transitions, then the first ChangeState per node."""
        ids = self._ids(context)
        names = [name.perform(context) for name in self.lifecycle_node_names]
        handlers: list[Action] = []
        firsts: list[Action] = []
        for name in names:
            emits = [EmitEvent(event=ChangeState(lifecycle_node_matcher=matches_node_name(name), transition_id=tid),
                               origin=self.origin) for tid in ids]
            firsts.append(emits[0])
            for done, following in zip(ids, emits[1:]):
                handlers.append(RegisterEventHandler(OnStateTransition(
                    matcher=_completes(name, done), entities=[following], origin=self.origin), origin=self.origin))
        return [*handlers, *firsts]


def _completes(node_name: str, transition_id: int) -> Any:
    """Whether a StateTransition event is `node_name` finishing transition `transition_id`."""
    start, goal = TRANSITION_STATES[transition_id]
    wanted = make_namespace_absolute(node_name)

    def matcher(event: Any) -> bool:
        return (isinstance(event, StateTransition) and getattr(event.action, 'node_name', None) == wanted
                and event.start_state == start and event.goal_state == goal)
    return matcher


