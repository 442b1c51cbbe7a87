"""Launch actions: one class per tag, registered with `@launch_tag`.

The split is launch's: `parse(entity, parser)` is a pure classmethod that validates the tag's
attributes and returns `(cls, kwargs)`; the parser then checks that no unknown key is left and
builds the action. `execute(context)` runs during resolution and returns the sub-actions to
visit next (a group returns its children between scope markers), so no action recurses itself.
Every action accepts `if:` or `unless:` (not both).
"""
from __future__ import annotations

import importlib
from typing import Any, ClassVar, NamedTuple, TypedDict

from zros.launch.entity import Entity, Scalar
from zros.launch.errors import LaunchFileError, Origin
from zros.launch.substitutions import SubstitutionError, Text, Typed, to_bool

__all__ = ['Action', 'ActionKwargs', 'Condition', 'Parser', 'launch_tag', 'registered_tags',
           'PushScope', 'PopScope', 'EnterFile', 'LeaveFile']

_TAGS: dict[str, type['Action']] = {}

# Modules that define tags; imported on first use so that `import zros.launch` stays cheap.
_TAG_MODULES = ('arg', 'env', 'group', 'include', 'log', 'process', 'ros', 'shutdown', 'timer')


def launch_tag(*names: str):
    """Class decorator: `@launch_tag('push_ros_namespace', 'push-ros-namespace')`."""
    def register(cls: type['Action']) -> type['Action']:
        cls.tag = names[0]
        for name in names:
            if name in _TAGS and _TAGS[name] is not cls:
                raise RuntimeError(f"launch tag '{name}' registered twice")
            _TAGS[name] = cls
        return cls
    return register


def _load_tags() -> None:
    for module in _TAG_MODULES:
        importlib.import_module(f'zros.launch.actions.{module}')


def registered_tags() -> dict[str, type['Action']]:
    _load_tags()
    return dict(_TAGS)


class Condition(NamedTuple):
    """`if: EXPR` (negate False) or `unless: EXPR` (negate True)."""

    expression: Text
    negate: bool

    def holds(self, context: Any) -> bool:
        text = self.expression.perform(context)
        try:
            value = to_bool(text)
        except SubstitutionError as exc:
            raise LaunchFileError(self.expression.origin, str(exc)) from None
        return value != self.negate


class ActionKwargs(TypedDict, total=False):
    origin: Origin
    condition: Condition | None


class Action:
    """Base of every launch action. Instances are built by `Parser.parse_action`."""

    tag: ClassVar[str] = ''

    def __init__(self, *, origin: Origin, condition: Condition | None = None) -> None:
        self.origin = origin
        self.condition = condition

    def __repr__(self) -> str:
        return f'<{type(self).__name__} {self.origin}>'

    @classmethod
    def parse(cls, entity: Entity, parser: 'Parser') -> tuple[type['Action'], ActionKwargs]:
        """The `if`/`unless` part every tag shares; subclasses extend the kwargs."""
        kwargs: ActionKwargs = {'origin': entity.origin}
        if_text = parser.text(entity, 'if', optional=True, data_type=Scalar)
        unless_text = parser.text(entity, 'unless', optional=True, data_type=Scalar)
        if if_text is not None and unless_text is not None:
            raise entity.error('unless', "'if' and 'unless' cannot be used together")
        if if_text is not None:
            kwargs['condition'] = Condition(if_text, False)
        elif unless_text is not None:
            kwargs['condition'] = Condition(unless_text, True)
        return cls, kwargs

    def visit(self, context: Any) -> list['Action']:
        """Check the condition, then execute."""
        if self.condition is not None and not self.condition.holds(context):
            return []
        return self.execute(context) or []

    def execute(self, context: Any) -> list['Action'] | None:
        return None

    def sub_actions(self) -> list['Action']:
        """Child actions known without resolving anything (for `--show-args`)."""
        return []


class Parser:
    """Turns entities into actions; carries the file being parsed."""

    def __init__(self, path: str) -> None:
        self.path = path

    def parse_action(self, entity: Entity) -> Action:
        tags = registered_tags()
        cls = tags.get(entity.type_name)
        if cls is None:
            known = ', '.join(sorted(tags))
            raise entity.error(None, f"unknown tag (known tags: {known})")
        action_cls, kwargs = cls.parse(entity, self)
        entity.assert_complete()
        return action_cls(**kwargs)

    def parse_actions(self, entities: list[Entity]) -> list[Action]:
        return [self.parse_action(entity) for entity in entities]

    # -- typed attribute helpers ---------------------------------------------------------------
    @staticmethod
    def text(entity: Entity, key: str, *, optional: bool = False, data_type: Any = str) -> Text | None:
        """A string attribute with substitutions, parsed (syntax errors name the key)."""
        value = entity.get_attr(key, data_type=data_type, optional=optional)
        if value is None:
            return None
        origin = entity.origin_of(key)
        return Text.parse(value, origin)

    @staticmethod
    def typed(entity: Entity, key: str, data_type: type, *, optional: bool = True) -> Typed | None:
        """A bool/int/float attribute, given as a YAML value or a string with substitutions."""
        value = entity.get_attr(key, data_type=Any, optional=optional)
        if value is None:
            return None
        return Typed.from_yaml(value, data_type, entity.origin_of(key))


# -- markers that actions return around their children --------------------------------------
class PushScope(Action):
    """Start of a scoped group: save configurations, environment and the ROS scope."""

    def __init__(self, *, origin: Origin, forwarding: bool = True, keep: list | None = None) -> None:
        super().__init__(origin=origin)
        self.forwarding = forwarding
        self.keep = keep or []

    def execute(self, context: Any) -> None:
        kept = {name: value.perform(context) for name, value in self.keep}
        context.push_scope()
        if not self.forwarding:
            context.reset_configurations(kept)


class PopScope(Action):
    def execute(self, context: Any) -> None:
        context.pop_scope()


class EnterFile(Action):
    """Start of an included file: `$(dirname)` / `$(filename)` now refer to it."""

    def __init__(self, *, origin: Origin, path: str) -> None:
        super().__init__(origin=origin)
        self.path = path

    def execute(self, context: Any) -> None:
        context.enter_file(self.path, self.origin)


class LeaveFile(Action):
    def execute(self, context: Any) -> None:
        context.leave_file()
