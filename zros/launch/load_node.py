"""launch_ros.actions.load_composable_nodes: `LoadComposableNodes` (zros.launch's) and
`get_composable_node_load_request`, the composition_interfaces/LoadNode request launch_ros
sends a component container for one ComposableNode description.

The request is built from the same scope the launch runs nodes in (zros.launch.context's
RosScope: pushed namespace, SetParameter, SetRemap), then the description's own name,
namespace, remappings and parameters; parameter files give the values that apply to the node
(its own entries and wildcards, as the node would read the file).
"""
from __future__ import annotations

from pathlib import Path
from typing import Any

from zros.launch.actions.composable import ComposableNode, LoadComposableNodes
from zros.launch.context import RosScope
from zros.launch.template import Text
from zros.launch_ros.utilities.namespace_utils import make_namespace_absolute, prefix_namespace
from zros.launch_ros.utilities.parameters import evaluate_parameters

__all__ = ['LoadComposableNodes', 'get_composable_node_load_request']


def get_composable_node_load_request(composable_node_description: ComposableNode, context: Any) -> Any:
    """The LoadNode request for `composable_node_description` in `context`, or None when its
    condition is false (the node is not loaded)."""
    from interfaces.composition_interfaces.srv import LoadNode
    description = composable_node_description
    if description.condition is not None and not description.condition.evaluate(context):
        return None
    scope = RosScope.of(context)
    request = LoadNode.Request()
    request.package_name = description.package.perform(context)
    request.plugin_name = description.plugin.perform(context)
    if description.name is not None:
        request.node_name = description.name.perform(context)
    namespace = description.namespace.perform(context) if description.namespace is not None else None
    combined = make_namespace_absolute(prefix_namespace(scope.namespace or None, namespace))
    if combined is not None:
        request.node_namespace = combined
    rules = [*scope.remaps, *(_pair(rule, description, context) for rule in description.remappings or [])]
    request.remap_rules = [f'{source}:={target}' for source, target in rules]
    node_fqn = f"{(combined or '').rstrip('/')}/{request.node_name}"
    values: list[tuple[str, Any]] = []
    for item in scope.params:
        values += [item] if isinstance(item, tuple) else _file_values(Path(item), node_fqn)
    for evaluated in evaluate_parameters(context, description.parameters):
        values += _file_values(evaluated, node_fqn) if isinstance(evaluated, Path) else list(evaluated.items())
    request.parameters = [_parameter_msg(name, value) for name, value in values]
    request.extra_arguments = [_parameter_msg(Text.of(name, description.origin).perform(context),
                                              _extra_value(value, description, context))
                               for name, value in _extra_pairs(description.extra_arguments)]
    return request


def _pair(rule: Any, description: ComposableNode, context: Any) -> tuple[str, str]:
    source, target = rule
    origin = description.origin.with_key('remappings')
    return Text.of(source, origin).perform(context), Text.of(target, origin).perform(context)


def _file_values(path: Path, node_fqn: str) -> list[tuple[str, Any]]:
    from zros.parameter import load_parameter_file
    return list(load_parameter_file(str(path.resolve()), node_fqn).items())


def _extra_pairs(extra: Any) -> list[tuple[Any, Any]]:
    """`extra_arguments`: Python gives a list of dicts, YAML `(name, value)` pairs."""
    pairs: list[tuple[Any, Any]] = []
    for item in extra or []:
        pairs += list(item.items()) if isinstance(item, dict) else [tuple(item)]
    return pairs


def _extra_value(value: Any, description: ComposableNode, context: Any) -> Any:
    from zros.parameter import parse_parameter_value
    if isinstance(value, (bool, int, float)):
        return value
    return parse_parameter_value(Text.of(value, description.origin).perform(context))


def _parameter_msg(name: str, value: Any) -> Any:
    from zros.parameter import Parameter
    return Parameter(name, value=value).to_parameter_msg()
