"""The ROS 2 managed-node state machine (design.ros2.org/articles/node_lifecycle.html) as data.

Primary states accept the public transitions (configure, cleanup, activate, deactivate,
shutdown); each moves the node into a transition state, where the user's callback runs and its
result (success, failure, error) picks the next primary state. Ids and labels are ROS 2
Humble's (lifecycle_msgs constants; `shutdown` for the three shutdown transitions,
`transition_success/failure/error` for the callback results), so `zros lifecycle` and
programs comparing labels with `'active'` see what they would in ROS. No transport here.
"""
from __future__ import annotations

import enum
from typing import NamedTuple

from zros.errors import RCLError

__all__ = ['LifecycleState', 'TransitionCallbackReturn', 'TransitionDescription', 'LifecycleStateMachine',
           'STATES', 'PUBLIC_TRANSITIONS', 'RESULT_TRANSITIONS', 'TransitionError', 'public_transition',
           'successful_steps']


class LifecycleState(NamedTuple):
    """A state as rclpy.lifecycle passes it to callbacks: `state.label`, `state.state_id`."""
    label: str
    state_id: int


class TransitionCallbackReturn(enum.IntEnum):
    """What a transition callback returns (lifecycle_msgs/Transition's TRANSITION_CALLBACK_*)."""
    SUCCESS = 97
    FAILURE = 98
    ERROR = 99

    def to_label(self) -> str:
        return f'transition_{self.name.lower()}'


class TransitionDescription(NamedTuple):
    transition_id: int
    label: str
    start: LifecycleState
    goal: LifecycleState


class TransitionError(RCLError):
    """A transition that the current state does not offer (what rclpy raises as `_rclpy.RCLError`)."""


UNKNOWN = LifecycleState('unknown', 0)
UNCONFIGURED = LifecycleState('unconfigured', 1)
INACTIVE = LifecycleState('inactive', 2)
ACTIVE = LifecycleState('active', 3)
FINALIZED = LifecycleState('finalized', 4)
CONFIGURING = LifecycleState('configuring', 10)
CLEANINGUP = LifecycleState('cleaningup', 11)
SHUTTINGDOWN = LifecycleState('shuttingdown', 12)
ACTIVATING = LifecycleState('activating', 13)
DEACTIVATING = LifecycleState('deactivating', 14)
ERRORPROCESSING = LifecycleState('errorprocessing', 15)

STATES = (UNKNOWN, UNCONFIGURED, INACTIVE, ACTIVE, FINALIZED,
          CONFIGURING, CLEANINGUP, SHUTTINGDOWN, ACTIVATING, DEACTIVATING, ERRORPROCESSING)

# id, label, start state, transition state
PUBLIC_TRANSITIONS = (
    TransitionDescription(1, 'configure', UNCONFIGURED, CONFIGURING),
    TransitionDescription(2, 'cleanup', INACTIVE, CLEANINGUP),
    TransitionDescription(3, 'activate', INACTIVE, ACTIVATING),
    TransitionDescription(4, 'deactivate', ACTIVE, DEACTIVATING),
    TransitionDescription(5, 'shutdown', UNCONFIGURED, SHUTTINGDOWN),
    TransitionDescription(6, 'shutdown', INACTIVE, SHUTTINGDOWN),
    TransitionDescription(7, 'shutdown', ACTIVE, SHUTTINGDOWN),
)

# transition state -> goal on (success, failure, error), with lifecycle_msgs' ids
_RESULTS = {
    CONFIGURING: (10, INACTIVE, UNCONFIGURED),
    CLEANINGUP: (20, UNCONFIGURED, INACTIVE),
    ACTIVATING: (30, ACTIVE, INACTIVE),
    DEACTIVATING: (40, INACTIVE, ACTIVE),
    SHUTTINGDOWN: (50, FINALIZED, FINALIZED),
    ERRORPROCESSING: (60, UNCONFIGURED, FINALIZED),
}
RESULT_TRANSITIONS = tuple(
    TransitionDescription(base + offset, result.to_label(), state,
                          (success, failure, FINALIZED if state is ERRORPROCESSING else ERRORPROCESSING)[offset])
    for state, (base, success, failure) in _RESULTS.items()
    for offset, result in enumerate(TransitionCallbackReturn))


def public_transition(transition_id: int) -> TransitionDescription:
    """The public transition with this id (lifecycle_msgs/Transition's TRANSITION_CONFIGURE = 1
    ... TRANSITION_ACTIVE_SHUTDOWN = 7); TransitionError for any other id."""
    for t in PUBLIC_TRANSITIONS:
        if t.transition_id == transition_id:
            return t
    offered = ', '.join(f'{t.transition_id} ({t.label} from {t.start.label})' for t in PUBLIC_TRANSITIONS)
    raise TransitionError(f'no public lifecycle transition with id {transition_id!r} (ids: {offered})')


def successful_steps(transition_id: int) -> tuple[TransitionDescription, TransitionDescription]:
    """The two steps a node publishes on `transition_event` when this public transition
    succeeds: into the transition state, then `transition_success` out of it (configure:
    unconfigured -> configuring, configuring -> inactive). What a launch that requested the
    transition reports to its OnStateTransition handlers."""
    begin = public_transition(transition_id)
    success = TransitionCallbackReturn.SUCCESS.to_label()
    end = next(t for t in RESULT_TRANSITIONS if t.start == begin.goal and t.label == success)
    return begin, end


class LifecycleStateMachine:
    """Current state plus the legal moves. Not thread-safe: the node serialises transitions."""

    def __init__(self) -> None:
        self.current = UNCONFIGURED

    @property
    def current_state(self) -> tuple[int, str]:
        """The current state as `(state_id, label)`, the pair rclpy's state machine reports."""
        return self.current.state_id, self.current.label

    def available_transitions(self) -> list[TransitionDescription]:
        return [t for t in PUBLIC_TRANSITIONS + RESULT_TRANSITIONS if t.start == self.current]

    def begin(self, transition: int | str) -> TransitionDescription:
        """Start a public transition (by id or label) from the current primary state; returns it
        and moves to its transition state. TransitionError when the state does not offer it."""
        for t in PUBLIC_TRANSITIONS:
            if t.start == self.current and (t.transition_id == transition or t.label == transition):
                self.current = t.goal
                return t
        offered = ', '.join(f'{t.label} [{t.transition_id}]' for t in self.available_transitions()) or 'none'
        raise TransitionError(f"transition '{transition}' is not available in state '{self.current.label}' "
                              f'(available: {offered})')

    def finish(self, result: TransitionCallbackReturn) -> TransitionDescription:
        """Leave the current transition state according to the callback's result."""
        for t in RESULT_TRANSITIONS:
            if t.start == self.current and t.label == result.to_label():
                self.current = t.goal
                return t
        raise TransitionError(f"state '{self.current.label}' is not a transition state")
