"""`GroupAction` (`group`, scoped children) and launch_ros's `PushRosNamespace`
(`push_ros_namespace` / `push-ros-namespace`)."""
from __future__ import annotations

from typing import Any, Iterable

from zros.errors import InvalidNameError
from zros.launch.action import Action, ActionKwargs, Parser, launch_tag
from zros.launch.actions.arg import (ResetLaunchConfigurations, SetLaunchConfiguration, configuration_pairs,
                                     parse_keep)
from zros.launch.actions.scope import ResetEnvironment, scoped
from zros.launch.context import RosScope
from zros.launch.entity import Entity
from zros.launch.errors import LaunchFileError, LaunchTypeError, Origin
from zros.launch.launch_description_entity import LaunchDescriptionEntity
from zros.launch.template import Text, Typed
from zros.names import validate_namespace

__all__ = ['GroupAction', 'PushRosNamespace', 'join_namespace', 'check_actions']


def check_actions(actions: Any, origin: Origin) -> list[Any]:
    """A list of actions given to a group, timer, event handler...: each must be a launch
    entity (an Action, a LaunchDescription, a user's LaunchDescriptionEntity), so a stray value fails where it was written. None entries
    are skipped, as launch skips them (a handler lambda's list of `os.remove(...)` results)."""
    if actions is None:
        return []
    if isinstance(actions, LaunchDescriptionEntity):
        actions = [actions]
    checked = []
    for item in actions:
        if item is None:
            continue
        if not isinstance(item, LaunchDescriptionEntity):
            raise LaunchTypeError(origin, f'expected launch actions, got {type(item).__name__}')
        checked.append(item)
    return checked


class GroupKwargs(ActionKwargs, total=False):
    actions: list[Action]
    scoped: Typed | None
    forwarding: Typed | None
    launch_configurations: list[tuple[Text, Text]] | None


@launch_tag('group')
class GroupAction(Action):
    """`GroupAction(actions, scoped=True, forwarding=True, launch_configurations=None)`;
    YAML `group: {scoped, forwarding, keep: [{name, value}], children: [...]}` or a bare list.

    Scoped (the default): configuration, environment, namespace, `SetParameter` and `SetRemap`
    changes made inside end with the group. `launch_configurations` are set for the group;
    with `forwarding=False` the group starts with those only, in the starting environment.
    `execute` returns the children between the stack actions (zros.launch.actions.scope).
    """

    def __init__(self, actions: Iterable[Action], *, scoped: Any = None, forwarding: Any = None,
                 launch_configurations: Any = None, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.actions = check_actions(actions, self.origin.with_key('actions'))
        self.scoped = self._typed(scoped, bool, 'scoped')
        self.forwarding = self._typed(forwarding, bool, 'forwarding')
        self.launch_configurations = configuration_pairs(self, launch_configurations, 'launch_configurations')

    @classmethod
    def parse(cls, entity: Entity, parser: Parser) -> tuple[type[Action], GroupKwargs]:
        _, kwargs = super().parse(entity, parser)
        if entity.is_mapping:
            kwargs['scoped'] = parser.typed(entity, 'scoped', bool)
            kwargs['forwarding'] = parser.typed(entity, 'forwarding', bool)
            kwargs['launch_configurations'] = parse_keep(entity, parser)
        kwargs['actions'] = parser.parse_actions(entity.children)
        return cls, kwargs

    def sub_actions(self) -> list[Action]:
        return self.actions

    def execute(self, context: Any) -> list[Action]:
        is_scoped = self.scoped.perform(context) if self.scoped is not None else True
        forwarding = self.forwarding.perform(context) if self.forwarding is not None else True
        sets: list[Action] = [SetLaunchConfiguration(name, value, origin=self.origin)
                              for name, value in self.launch_configurations]
        if not is_scoped:
            return [*sets, *self.actions]
        if forwarding:
            return scoped(self.actions, self.origin, first=sets)
        resets = [ResetEnvironment(origin=self.origin),
                  ResetLaunchConfigurations(self.launch_configurations, origin=self.origin)]
        return scoped(self.actions, self.origin, first=resets)


def join_namespace(base: str, namespace: str) -> str:
    """launch_ros's rule: a relative namespace goes under `base`, an absolute one replaces it;
    the result is absolute ('/' for the root)."""
    namespace = namespace.strip()
    if not namespace.startswith('/'):
        namespace = f"{base.rstrip('/')}/{namespace}"
    namespace = '/' + namespace.strip('/')
    return namespace


class PushNamespaceKwargs(ActionKwargs, total=False):
    namespace: Text


@launch_tag('push_ros_namespace', 'push-ros-namespace')
class PushRosNamespace(Action):
    """`PushRosNamespace(namespace)`; YAML `push_ros_namespace: {namespace}`: later nodes in
    the scope go under this namespace."""

    def __init__(self, namespace: Any, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.namespace = self._text(namespace, 'namespace')

    @classmethod
    def parse(cls, entity: Entity, parser: Parser) -> tuple[type[Action], PushNamespaceKwargs]:
        _, kwargs = super().parse(entity, parser)
        kwargs['namespace'] = parser.text(entity, 'namespace')
        return cls, kwargs

    def execute(self, context: Any) -> None:
        scope = RosScope.of(context)
        namespace = join_namespace(scope.namespace or '/', self.namespace.perform(context))
        try:
            validate_namespace(namespace)
        except InvalidNameError as exc:
            raise LaunchFileError(self.namespace.origin, str(exc)) from None
        scope.namespace = namespace
