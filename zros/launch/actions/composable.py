"""Composable nodes: `ComposableNodeContainer` (`node_container`), `LoadComposableNodes`
(`load_composable_node`) and the `ComposableNode` description.

zros has no component containers of its own (no shared-library plugins to load), so a
composable node of a container the launch starts runs as its own process: its plugin
`pkg_ns::ClassName` names an executable of its package (`ClassName`, or `class_name`), started
like a `Node` with the same name, namespace, parameters and remappings. The container itself is
not started; a one-line note in the launch output says so.

A `LoadComposableNodes` aimed at a container this launch does not start (one already running,
or a node of anyone's that serves `~/_container/load_node`) does what launch_ros does: it sends
the container one LoadNode request per node (zros.launch.load_node).
"""
from __future__ import annotations

import re
from typing import Any

from zros.launch.action import Action, ActionKwargs, Parser, launch_tag
from zros.launch.actions.process import Node
from zros.launch.conditions import Condition
from zros.launch.entity import Entity, Scalar
from zros.launch.errors import LaunchFileError, Origin
from zros.launch.namespace_utils import make_namespace_absolute
from zros.launch.origin import origin_here
from zros.launch.parameters import param_entries, yaml_param_entries
from zros.launch.plan import LogMessage
from zros.launch.template import Text

__all__ = ['ComposableNode', 'ComposableNodeContainer', 'LoadComposableNodes', 'plugin_executables']


def plugin_executables(plugin: str) -> list[str]:
    """Executable names a plugin class may have in zros: `composition::Talker` -> Talker,
    talker; `ns::ImageViewerNode` -> ImageViewerNode, image_viewer_node, image_viewer."""
    cls = plugin.split('::')[-1].split('.')[-1]
    snake = re.sub(r'(?<=[a-z0-9])([A-Z])|(?<=[A-Z])([A-Z])(?=[a-z])', r'_\1\2', cls).lower()
    names = [cls, snake]
    for suffix in ('_node', '_component'):
        if snake.endswith(suffix):
            names.append(snake[:-len(suffix)])
    return list(dict.fromkeys(names))


class ComposableNode:
    """`ComposableNode(package, plugin, name, namespace, parameters, remappings,
    extra_arguments, condition)` (launch_ros.descriptions)."""

    def __init__(self, *, package: Any, plugin: Any, name: Any = None, namespace: Any = None,
                 parameters: Any = None, remappings: Any = None, extra_arguments: Any = None,
                 condition: Condition | None = None, origin: Origin | None = None) -> None:
        self.origin = origin or origin_here('ComposableNode')
        self.package = Text.of(package, self.origin.with_key('package'))
        self.plugin = Text.of(plugin, self.origin.with_key('plugin'))
        self.name = None if name is None else Text.of(name, self.origin.with_key('name'))
        self.namespace = None if namespace is None else Text.of(namespace, self.origin.with_key('namespace'))
        self.parameters = parameters if isinstance(parameters, tuple) else param_entries(
            parameters, self.origin.with_key('parameters'))
        self.remappings = remappings
        self.extra_arguments = extra_arguments   # container options (intra-process...): no meaning here
        self.condition = condition

    @classmethod
    def parse(cls, entity: Entity, parser: Parser) -> 'ComposableNode':
        """A YAML `composable_node` item (not a tag: it has no condition of its own but `if`)."""
        _, kwargs = Action.parse(entity, parser)
        remaps = []
        for item in entity.get_attr('remap', data_type=list[Entity], optional=True) or []:
            remaps.append((parser.text(item, 'from'), parser.text(item, 'to')))
            item.assert_complete()
        extra = []
        for item in entity.get_attr('extra_arg', data_type=list[Entity], optional=True) or []:
            extra.append((parser.text(item, 'name'), parser.text(item, 'value', data_type=Scalar)))
            item.assert_complete()
        node = cls(package=parser.text(entity, 'pkg'), plugin=parser.text(entity, 'plugin'),
                   name=parser.text(entity, 'name', optional=True),
                   namespace=parser.text(entity, 'namespace', optional=True),
                   parameters=yaml_param_entries(entity, parser), remappings=remaps, extra_arguments=extra,
                   condition=kwargs.get('condition'), origin=entity.origin)
        entity.assert_complete()
        return node

    def as_node(self, context: Any, output: Text | None) -> Node:
        """The Node action that runs this composable node as a process."""
        from zros.ament_index_python.executables import executables
        package = self.package.perform(context)
        plugin = self.plugin.perform(context)
        candidates = plugin_executables(plugin)
        available = executables(package)
        executable = next((name for name in candidates if name in available), None)
        if executable is None:
            raise LaunchFileError(self.plugin.origin, f"composable node plugin '{plugin}': no executable "
                                  f"{' or '.join(candidates)} in package '{package}' (zros runs composable "
                                  f"nodes as processes; executables: {', '.join(available) or 'none'})")
        return _ComponentNode(package=self.package, executable=executable, name=self.name, namespace=self.namespace,
                              parameters=self.parameters, remappings=self.remappings, output=output,
                              origin=self.origin)


class _ComponentNode(Node):
    """The process a composable node runs as. launch_ros counts a loaded component under the
    full name its container reports, which always exists: the namespace given or pushed, else
    '/', and the name given, else the component's own; zros's component executables name their
    node after themselves (composition::Listener runs `listener`, node 'listener')."""

    def _counted_name(self, context: Any) -> str | None:
        name, namespace = self.resolve_names(context)
        return f"{(namespace or '/').rstrip('/')}/{name or self.executable.perform(context)}"


def _note(context: Any, origin: Origin, where: str, nodes: list[Node]) -> None:
    names = ', '.join(f"'{node.given_name.perform(context) if node.given_name else node.executable}'" for node in nodes)
    context.emit(LogMessage('INFO', f'zros has no component containers: composable node{"s" if len(nodes) > 1 else ""} '
                                    f'{names} of {where} run{"" if len(nodes) > 1 else "s"} as '
                                    f'{"their own processes" if len(nodes) > 1 else "its own process"}', origin))


def _selected(context: Any, descriptions: list[ComposableNode], output: Text | None) -> list[Node]:
    return [description.as_node(context, output) for description in descriptions
            if description.condition is None or description.condition.evaluate(context)]


def _descriptions(owner: Action, values: Any) -> list[ComposableNode]:
    items = list(values or [])
    for item in items:
        if not isinstance(item, ComposableNode):
            raise LaunchFileError(owner.origin.with_key('composable_node_descriptions'),
                                  f'expected ComposableNode descriptions, got {type(item).__name__}')
    return items


class ContainerKwargs(ActionKwargs, total=False):
    composable_node_descriptions: list[ComposableNode]


@launch_tag('node_container')
class ComposableNodeContainer(Node):
    """`ComposableNodeContainer(name, namespace, package, executable,
    composable_node_descriptions=[...])`; YAML `node_container: {..., composable_node: [...]}`.
    The container is not started; each composable node runs as its own process."""

    def __init__(self, *, composable_node_descriptions: Any = None, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.composable_node_descriptions = _descriptions(self, composable_node_descriptions)

    @classmethod
    def parse(cls, entity: Entity, parser: Parser) -> tuple[type[Action], ContainerKwargs]:
        _, kwargs = super().parse(entity, parser)
        kwargs['composable_node_descriptions'] = [
            ComposableNode.parse(item, parser)
            for item in entity.get_attr('composable_node', data_type=list[Entity], optional=True) or []]
        return cls, kwargs

    def execute(self, context: Any) -> list[Action]:
        nodes = _selected(context, self.composable_node_descriptions, self.output)
        self._perform_substitutions(context)
        self._count_node_name(context)   # the container is a node of the launch, as in launch_ros
        name, namespace = self.resolve_names(context)
        container = f"{(namespace or '/').rstrip('/')}/{name or self.executable.perform(context)}"
        context.containers.add(container)
        if nodes:
            _note(context, self.origin, f"container '{container}'", nodes)
        return nodes


class LoadKwargs(ActionKwargs, total=False):
    target_container: Text
    composable_node_descriptions: list[ComposableNode]


@launch_tag('load_composable_node')
class LoadComposableNodes(Action):
    """`LoadComposableNodes(target_container=..., composable_node_descriptions=[...])`;
    YAML `load_composable_node: {target, composable_node: [...]}`. Into a container this launch
    starts (its action, or the name of a ComposableNodeContainer or rclcpp_components Node
    executed before), each node runs as its own process; into any other, the container gets
    launch_ros's LoadNode requests, in order, and the launch waits for its answers."""

    def __init__(self, *, composable_node_descriptions: Any, target_container: Any = None, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.target_container = target_container
        self.composable_node_descriptions = _descriptions(self, composable_node_descriptions)

    @classmethod
    def parse(cls, entity: Entity, parser: Parser) -> tuple[type[Action], LoadKwargs]:
        _, kwargs = super().parse(entity, parser)
        kwargs['target_container'] = parser.text(entity, 'target')
        kwargs['composable_node_descriptions'] = [
            ComposableNode.parse(item, parser)
            for item in entity.get_attr('composable_node', data_type=list[Entity])]
        return cls, kwargs

    def execute(self, context: Any) -> list[Action]:
        target = self.target_container
        if isinstance(target, Node):
            where = "the container" if target.given_name is None else f"container '{target.given_name.perform(context)}'"
        elif target is not None:
            name = make_namespace_absolute(Text.of(target, self.origin.with_key('target_container')).perform(context))
            if name not in context.containers:
                self._load_into(name, context)
                return []
            where = f"container '{name}'"
        else:
            where = 'the container'
        nodes = _selected(context, self.composable_node_descriptions, None)
        if nodes:
            _note(context, self.origin, where, nodes)
        return nodes

    def _load_into(self, container: str, context: Any) -> None:
        """launch_ros's way, for a container the launch does not start: the requests are built
        now (the scope of a GroupAction ends after this) and sent by the supervisor."""
        from zros.launch.load_node import get_composable_node_load_request, load_task
        requests = [request for request in (get_composable_node_load_request(description, context)
                                            for description in self.composable_node_descriptions)
                    if request is not None]
        if requests:
            context.emit(load_task(container, requests, context, self.origin))
