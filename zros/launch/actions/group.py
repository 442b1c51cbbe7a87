"""`group` (scoped children) and `push_ros_namespace` / `push-ros-namespace`."""
from __future__ import annotations

from typing import Any

from zros.errors import InvalidNameError
from zros.launch.actions import Action, ActionKwargs, Parser, PopScope, PushScope, launch_tag
from zros.launch.entity import Entity, Scalar
from zros.launch.errors import LaunchFileError
from zros.launch.substitutions import Text, Typed
from zros.names import validate_namespace

__all__ = ['Group', 'PushRosNamespace', 'join_namespace']


class GroupKwargs(ActionKwargs, total=False):
    scoped: Typed | None
    forwarding: Typed | None
    keep: list[tuple[str, Text]]
    children: list[Action]


@launch_tag('group')
class Group(Action):
    """`group: {scoped: true, forwarding: true, keep: [{name, value}], children: [...]}` or a
    bare list of children.

    Scoped (the default): configuration, environment, namespace, `set_parameter` and
    `set_remap` changes made inside end with the group. `forwarding: false` starts the group
    with no configurations but those in `keep`.
    """

    def __init__(self, *, children: list[Action], scoped: Typed | None = None,
                 forwarding: Typed | None = None, keep: list | None = None, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.children = children
        self.scoped, self.forwarding, self.keep = scoped, forwarding, keep or []

    @classmethod
    def parse(cls, entity: Entity, parser: Parser) -> tuple[type[Action], GroupKwargs]:
        _, kwargs = super().parse(entity, parser)
        if entity.is_mapping:
            kwargs['scoped'] = parser.typed(entity, 'scoped', bool)
            kwargs['forwarding'] = parser.typed(entity, 'forwarding', bool)
            keep = []
            for item in entity.get_attr('keep', data_type=list[Entity], optional=True) or []:
                keep.append((item.get_attr('name'), parser.text(item, 'value', data_type=Scalar)))
                item.assert_complete()
            kwargs['keep'] = keep
        kwargs['children'] = parser.parse_actions(entity.children)
        return cls, kwargs

    def sub_actions(self) -> list[Action]:
        return self.children

    def execute(self, context: Any) -> list[Action]:
        scoped = self.scoped.perform(context) if self.scoped is not None else True
        forwarding = self.forwarding.perform(context) if self.forwarding is not None else True
        if not scoped:
            return list(self.children)
        return [PushScope(origin=self.origin, forwarding=forwarding, keep=self.keep),
                *self.children, PopScope(origin=self.origin)]


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
    """`push_ros_namespace: {namespace}`: later nodes in the scope go under this namespace."""

    def __init__(self, *, namespace: Text, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.namespace = namespace

    @classmethod
    def parse(cls, entity: Entity, parser: Parser) -> tuple[type[Action], PushNamespaceKwargs]:
        _, kwargs = super().parse(entity, parser)
        kwargs['namespace'] = parser.text(entity, 'namespace')
        return cls, kwargs

    def execute(self, context: Any) -> None:
        namespace = join_namespace(context.ros.namespace or '/', self.namespace.perform(context))
        try:
            validate_namespace(namespace)
        except InvalidNameError as exc:
            raise LaunchFileError(self.namespace.origin, str(exc)) from None
        context.ros.namespace = namespace
