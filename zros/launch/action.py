"""The launch action: one class per construct, built by either front end.

The model is launch's. A Python launch file constructs actions directly with ROS 2's keyword
arguments (`Node(package=..., parameters=[...])`); the YAML front end reads a tag and calls the
same constructor with the same keywords, through `parse(entity, parser)`, a pure classmethod
that validates the tag's attributes and returns `(cls, kwargs)` (the parser then checks that no
unknown key is left). Constructors turn whatever they are given (strings, Substitutions, YAML
`Text`) into `Text` / `Typed` values that remember where they were written.

The tags and the parser are launch.frontend's (zros.launch.frontend): `launch_tag` exposes a
class as `expose_action` does, and `Parser` is the one parser of XML and YAML files.

`execute(context)` runs during resolution and returns the sub-actions to visit next (a group
returns its children between scope markers), so no action recurses itself. Every action takes a
`condition` (`if:` / `unless:` in YAML).
"""
from __future__ import annotations

from typing import Any, Callable, ClassVar, TypedDict

from zros.launch.conditions import Condition, IfCondition, UnlessCondition
from zros.launch.entity import Entity, Scalar
from zros.launch.errors import LaunchFileError, Origin
from zros.launch.frontend.expose import action_parse_methods, expose_action
from zros.launch.frontend.parser import Parser
from zros.launch.launch_description_entity import LaunchDescriptionEntity
from zros.launch.origin import origin_here
from zros.launch.template import Text, Typed

__all__ = ['Action', 'ActionKwargs', 'Parser', 'launch_tag', 'registered_tags',
           'EnterFile', 'LeaveFile', 'EndCapture', 'report_completion']


def launch_tag(*names: str) -> Callable[[type['Action']], type['Action']]:
    """Class decorator: `@launch_tag('push_ros_namespace', 'push-ros-namespace')`, launch's
    `expose_action` for each spelling, plus the class's `tag` (its first name)."""
    def register(cls: type['Action']) -> type['Action']:
        cls.tag = names[0]
        for name in names:
            expose_action(name)(cls)
        return cls
    return register


def registered_tags() -> dict[str, Callable[..., Any]]:
    """Every tag a launch file may use, with its parse method (zros's and extensions')."""
    Parser.load_launch_extensions()
    return dict(action_parse_methods)


class ActionKwargs(TypedDict, total=False):
    origin: Origin
    condition: Condition | None


class Action(LaunchDescriptionEntity):
    """Base of every launch action.

    Args:
        condition: run the action only when this holds.
        origin: where the action was written; YAML passes the entity's, Python leaves it
            None and the caller's file and line are used.
    """

    tag: ClassVar[str] = ''
    #: Its work ends when its process exits, not when it is executed (ExecuteProcess): the
    #: launch reports its ExecutionComplete then.
    completes_on_exit: ClassVar[bool] = False

    def __init__(self, *, condition: Condition | None = None, origin: Origin | None = None, **unknown: Any) -> None:
        self.origin = origin or origin_here(type(self).__name__)
        if unknown:
            name = next(iter(unknown))
            raise LaunchFileError(self.origin.with_key(name), f'{type(self).__name__} takes no argument {name!r}')
        if condition is not None and not isinstance(condition, Condition):
            raise LaunchFileError(self.origin.with_key('condition'),
                                  f'expected a Condition (IfCondition, UnlessCondition, ...), '
                                  f'got {type(condition).__name__}')
        self.condition = condition

    def __repr__(self) -> str:
        return f'<{type(self).__name__} {self.origin}>'

    def describe(self) -> str:
        return repr(self)

    # -- Python values -> deferred values, located at this action's key ------------------------
    def _text(self, value: Any, key: str) -> Text:
        return Text.of(value, self.origin.with_key(key))

    def _optional_text(self, value: Any, key: str) -> Text | None:
        return None if value is None else self._text(value, key)

    def _typed(self, value: Any, data_type: type, key: str) -> Typed | None:
        return None if value is None else Typed.of(value, data_type, self.origin.with_key(key))

    # -- YAML ------------------------------------------------------------------------------------
    @classmethod
    def parse(cls, entity: Entity, parser: 'Parser') -> tuple[type['Action'], ActionKwargs]:
        """The `if`/`unless` part every tag shares; subclasses extend the kwargs."""
        kwargs: ActionKwargs = {'origin': entity.origin}
        if_text = parser.text(entity, 'if', optional=True, data_type=Scalar)
        unless_text = parser.text(entity, 'unless', optional=True, data_type=Scalar)
        if if_text is not None and unless_text is not None:
            raise entity.error('unless', "'if' and 'unless' cannot be used together")
        if if_text is not None:
            kwargs['condition'] = IfCondition(if_text, origin=if_text.origin)
        elif unless_text is not None:
            kwargs['condition'] = UnlessCondition(unless_text, origin=unless_text.origin)
        return cls, kwargs

    # -- resolution ------------------------------------------------------------------------------
    def visit(self, context: Any) -> list['Action'] | None:
        """Check the condition, then execute; None when there is nothing to visit next."""
        if self.condition is not None and not self.condition.evaluate(context):
            return None
        result = self.execute(context)
        if not self.completes_on_exit:
            report_completion(self, context)
        return None if result is None else list(result)

    def execute(self, context: Any) -> list['Action'] | None:
        return None

    def sub_actions(self) -> list['Action']:
        """Child actions known without resolving anything (for `--show-args`)."""
        return []

    def describe_sub_entities(self) -> list['Action']:
        """launch's name for `sub_actions()`."""
        return self.sub_actions()


def report_completion(action: Action, context: Any) -> None:
    """Queue ExecutionComplete for `action` if a handler on the context would take it (launch
    emits it only then, so a launch without OnExecutionComplete pays nothing)."""
    from zros.launch.events.execution_complete import ExecutionComplete
    would_handle = getattr(context, 'would_handle_event', None)
    if would_handle is None:
        return
    event = ExecutionComplete(action=action)
    if would_handle(event):
        context.emit_event_sync(event)


# -- markers that actions return around their children --------------------------------------
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


class EndCapture(Action):
    """Closes the effect capture begun by the action before it (`context.begin_capture()`) and
    emits the captured effects wrapped: a timer's, an event handler's."""

    def __init__(self, *, origin: Origin, wrap: Any) -> None:
        super().__init__(origin=origin)
        self.wrap = wrap

    def execute(self, context: Any) -> None:
        context.emit(self.wrap(context.end_capture()))
