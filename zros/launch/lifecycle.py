"""The launch's side of lifecycle nodes (launch_ros's `LifecycleNode`, `ChangeState`,
`StateTransition`, `OnStateTransition`), as Jazzy's slam_toolbox launch files use them:

    node = LifecycleNode(package='slam_toolbox', executable='async_slam_toolbox_node',
                         name='slam_toolbox', namespace='')
    EmitEvent(event=ChangeState(lifecycle_node_matcher=matches_action(node),
                                transition_id=Transition.TRANSITION_CONFIGURE))
    RegisterEventHandler(OnStateTransition(target_lifecycle_node=node, start_state='configuring',
                                           goal_state='inactive', entities=[...]))

The supervisor has no ROS node, so a `ChangeState` becomes a child command,
`zros lifecycle set NODE TRANSITION --wait S`, run once the node's process has started (it
waits for the node's lifecycle services). When it succeeds, the supervisor reports the two steps
the node went through (configure: unconfigured -> configuring, configuring -> inactive) to the
OnStateTransition handlers. Transitions made by anyone else (a lifecycle manager,
`zros lifecycle set` in a terminal) are not seen: launch_ros watches `<node>/transition_event`
for those.
"""
from __future__ import annotations

from typing import Any, Callable, NamedTuple

from zros.launch.actions.process import Node
from zros.launch.errors import LaunchFileError, Origin
from zros.launch.event_handlers.on_action_event_base import OnActionEventBase
from zros.launch.origin import origin_here
from zros.launch.template import Text

__all__ = ['LifecycleNode', 'ChangeState', 'StateTransition', 'OnStateTransition', 'StateTransitionFilter',
           'TRANSITION_WAIT_S']

#: [s] how long a requested transition waits for the node's lifecycle services to appear.
TRANSITION_WAIT_S = 120.0


class LifecycleNode(Node):
    """`LifecycleNode(name=..., namespace=..., ...)`: a Node whose executable is a lifecycle node.
    The launch can request its transitions (`EmitEvent(event=ChangeState(...))`), and its
    process gets `ZROS_LIFECYCLE_LAUNCH=1` so that a node which brings itself up when started
    the Humble way (slam_toolbox) waits for them instead (zros.lifecycle.autostart)."""

    def __init__(self, *, name: Any, namespace: Any, **kwargs: Any) -> None:
        super().__init__(name=name, namespace=namespace, **kwargs)

    def process_options(self, context: Any) -> dict[str, Any]:
        from zros.lifecycle.autostart import LIFECYCLE_LAUNCH_ENV
        options = super().process_options(context)
        options['env'] = (*options['env'], (LIFECYCLE_LAUNCH_ENV, '1'))
        options['lifecycle'] = True
        return options


class ChangeState:
    """`ChangeState(lifecycle_node_matcher=matches_action(node), transition_id=...)`: the event
    that asks lifecycle nodes of this launch for a transition (lifecycle_msgs/Transition's ids:
    TRANSITION_CONFIGURE = 1 ... TRANSITION_ACTIVE_SHUTDOWN = 7). The matcher is called with each
    LifecycleNode action whose process is running when the event is emitted."""

    def __init__(self, *, lifecycle_node_matcher: Callable[[Any], bool], transition_id: int,
                 origin: Origin | None = None) -> None:
        from zros.lifecycle.state_machine import TransitionError, public_transition
        from zros.launch.events import ActionMatcher
        self.origin = origin or origin_here('ChangeState')
        if not callable(lifecycle_node_matcher):
            raise LaunchFileError(self.origin.with_key('lifecycle_node_matcher'),
                                  'expected a matcher such as launch.events.matches_action(node), '
                                  f'got {type(lifecycle_node_matcher).__name__}')
        if isinstance(lifecycle_node_matcher, ActionMatcher) and not isinstance(lifecycle_node_matcher.target,
                                                                                LifecycleNode):
            raise LaunchFileError(self.origin.with_key('lifecycle_node_matcher'),
                                  f'matches_action() names a {type(lifecycle_node_matcher.target).__name__}; '
                                  'only a LifecycleNode has lifecycle transitions')
        try:
            self.transition = public_transition(transition_id)
        except TransitionError as exc:
            raise LaunchFileError(self.origin.with_key('transition_id'), str(exc)) from None
        self.lifecycle_node_matcher = lifecycle_node_matcher
        self.transition_id = transition_id

    def __repr__(self) -> str:
        return f'<ChangeState {self.transition.label} [{self.transition_id}]>'


class StateTransition(NamedTuple):
    """A step a lifecycle node of the launch went through (launch_ros's StateTransition event):
    what an OnStateTransition `matcher` receives. Labels are lifecycle_msgs' ('configure',
    'transition_success'; 'unconfigured', 'configuring', 'inactive', ...)."""

    action: Any
    transition: str
    start_state: str
    goal_state: str
    process_name: str


class StateTransitionFilter(NamedTuple):
    """Which steps an OnStateTransition handler fires on, resolved (None: any)."""

    transition: str | None = None
    start_state: str | None = None
    goal_state: str | None = None
    matcher: Callable[[StateTransition], bool] | None = None

    def matches(self, event: StateTransition) -> bool:
        if self.matcher is not None:
            return bool(self.matcher(event))
        return all(wanted is None or wanted == got for wanted, got in (
            (self.transition, event.transition), (self.start_state, event.start_state),
            (self.goal_state, event.goal_state)))

    def describe(self) -> str:
        if self.matcher is not None:
            return f'matched by {getattr(self.matcher, "__name__", self.matcher)}'
        states = f"{self.start_state or 'any state'} -> {self.goal_state or 'any state'}"
        return (f"'{self.transition}' " if self.transition else '') + states


class OnStateTransition(OnActionEventBase):
    """`OnStateTransition(target_lifecycle_node=node, transition=, start_state=, goal_state=,
    entities=[...])`, or `matcher=f(event)` instead of the filters (launch_ros's rule: then the
    others are not considered). Fires on the steps of transitions this launch requested."""

    event, _key, event_type = 'transition', 'entities', StateTransition

    def __init__(self, *, entities: Any, target_lifecycle_node: Any = None, transition: Any = None,
                 start_state: Any = None, goal_state: Any = None, matcher: Any = None,
                 origin: Origin | None = None, **_: Any) -> None:
        origin = origin or origin_here('OnStateTransition')
        if target_lifecycle_node is not None and not isinstance(target_lifecycle_node, LifecycleNode):
            raise LaunchFileError(origin.with_key('target_lifecycle_node'),
                                  f'expected a LifecycleNode action, got {type(target_lifecycle_node).__name__}')
        if callable(entities) and not isinstance(entities, (list, tuple)):
            raise LaunchFileError(origin.with_key('entities'), 'expected launch actions, got a function')
        if matcher is not None and not callable(matcher):
            raise LaunchFileError(origin.with_key('matcher'), f'expected a function of the event, '
                                                              f'got {type(matcher).__name__}')
        super().__init__(target_action=None if matcher is not None else target_lifecycle_node,
                         entities=entities, origin=origin)
        self.matcher = matcher
        self.filters = {key: None if value is None else Text.of(value, origin.with_key(key))
                        for key, value in (('transition', transition), ('start_state', start_state),
                                           ('goal_state', goal_state))}

    def transition_filter(self, context: Any) -> StateTransitionFilter:
        """The filters resolved; an unknown state or transition label is an error now, since
        a handler waiting for it would never fire."""
        from zros.lifecycle.state_machine import PUBLIC_TRANSITIONS, RESULT_TRANSITIONS, STATES
        if self.matcher is not None:
            return StateTransitionFilter(matcher=self.matcher)
        known = {'transition': sorted({t.label for t in PUBLIC_TRANSITIONS + RESULT_TRANSITIONS}),
                 'start_state': [s.label for s in STATES], 'goal_state': [s.label for s in STATES]}
        values = {}
        for key, text in self.filters.items():
            value = None if text is None else text.perform(context)
            if value is not None and value not in known[key]:
                raise LaunchFileError(text.origin, f"unknown {'transition' if key == 'transition' else 'state'} "
                                                   f"'{value}' (known: {', '.join(known[key])})")
            values[key] = value
        return StateTransitionFilter(**values)
