"""Loading composable nodes into a component container the launch does not start, as
launch_ros's LoadComposableNodes does: one composition_interfaces/LoadNode request per node,
sent in order to `<container>/_container/load_node`.

`get_composable_node_load_request` builds the request launch_ros sends for one ComposableNode
description, from the same scope the launch runs nodes in (zros.launch.context's RosScope:
pushed namespace, SetParameter, SetRemap), then the description's own name, namespace,
remappings and parameters; parameter files give the values that apply to the node (its own
entries and wildcards, as the node would read the file).

`load_task` turns the requests into a TaskEffect: the supervisor runs it on a thread of its own
(the container may take long to appear or to answer) and the launch does not end before it has.
launch_ros waits for the service without end; zros waits `SERVICE_WAIT_S` and then fails the
launch with one error line, so a mistyped container name is an exit code rather than a hang.
"""
from __future__ import annotations

import os
import threading
from pathlib import Path
from typing import TYPE_CHECKING, Any

from zros.launch.context import RosScope
from zros.launch.errors import LaunchError, Origin
from zros.launch.namespace_utils import make_namespace_absolute, prefix_namespace
from zros.launch.parameter_evaluation import evaluate_parameters
from zros.launch.plan import CallEffect, LogMessage, TaskEffect
from zros.launch.template import Text

if TYPE_CHECKING:
    from zros.launch.actions.composable import ComposableNode

__all__ = ['get_composable_node_load_request', 'load_task', 'SERVICE_WAIT_S']

#: [s] how long the launch waits for a container it did not start to offer its load service.
SERVICE_WAIT_S = 30.0
_POLL_S = 1.0          # [s] how often a wait looks whether the launch is shutting down
_LOGGER = 'launch_ros.actions.load_composable_nodes'


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
    """launch_ros's reading of a parameter file for a LoadNode request (not rcl's): the `/**`
    entry's values, updated by those of the entry that names the node exactly (so the node's
    own win wherever they are written); a file with no `ros__parameters` at all is itself the
    node's parameters."""
    import yaml

    from zros.parameter import flatten_parameters
    document = yaml.safe_load(path.read_text(encoding='utf-8')) or {}
    sections = dict(_sections(document, ()))
    if not sections:
        return list(flatten_parameters(document).items())
    values = dict(sections.get('**') or {})
    values.update(sections.get(node_fqn.strip('/')) or {})
    return list(flatten_parameters(values).items())


def _sections(tree: dict, keys: tuple[str, ...]) -> list[tuple[str, dict]]:
    """(node key, parameters) for each `ros__parameters` of a file, the namespaces and node name
    above it joined with '/' and without leading slashes (`/ns: {/node: ...}` is 'ns/node')."""
    if 'ros__parameters' in tree:
        return [('/'.join(keys), tree['ros__parameters'])]
    found: list[tuple[str, dict]] = []
    for key, value in tree.items():
        if isinstance(value, dict):
            found += _sections(value, (*keys, str(key).lstrip('/')))
    return found


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


def load_task(target: str, requests: list[Any], context: Any, origin: Origin | None) -> TaskEffect:
    """The TaskEffect that loads `requests` into the container named `target` (fully qualified),
    in order; each loaded node is counted in `context.node_names` (get_node_name_count)."""
    service = f"{target.rstrip('/')}/_container/load_node"

    def run(stop: threading.Event) -> list[Any]:
        from interfaces.composition_interfaces.srv import LoadNode
        from zros.context import Context
        from zros.node import Node
        with Context().init([], install_signal_handlers=False) as ros:
            node = Node(f'launch_ros_{os.getpid()}', context=ros)
            try:
                client = node.create_client(LoadNode, service)
                if not _wait_for_service(client, stop):
                    if stop.is_set():
                        return [LogMessage('WARNING', f"Abandoning wait for the '{service}' service, due to "
                                                      'shutdown.', origin, _LOGGER)]
                    raise LaunchError(f"LoadComposableNodes: no container offers '{service}' after "
                                      f'{SERVICE_WAIT_S:g} s (is container {target!r} running?)')
                effects: list[Any] = []
                for request in requests:
                    response = _call(client, request, stop)
                    if response is None:
                        effects.append(LogMessage('WARNING', f"Abandoning wait for the '{service}' service "
                                                             'response, due to shutdown.', origin, _LOGGER))
                        break
                    effects += _outcome(request, response, target, context, origin)
                return effects
            finally:
                node.destroy_node()

    count = len(requests)
    return TaskEffect(f"load {count} composable node{'s' if count > 1 else ''} into container '{target}' "
                      f'(service {service})', run, origin)


def _wait_for_service(client: Any, stop: threading.Event) -> bool:
    waited = 0.0
    while waited < SERVICE_WAIT_S and not stop.is_set():
        if client.wait_for_service(timeout_sec=min(_POLL_S, SERVICE_WAIT_S - waited)):
            return True
        waited += _POLL_S
    return False


def _call(client: Any, request: Any, stop: threading.Event) -> Any:
    """The container's response, or None when the launch shut down first (launch_ros waits for
    the answer as long as the launch runs)."""
    answered = threading.Event()
    future = client.call_async(request)
    future.add_done_callback(lambda _: answered.set())
    while not answered.wait(_POLL_S):
        if stop.is_set():
            future.cancel()
            return None
    return future.result()


def _outcome(request: Any, response: Any, target: str, context: Any, origin: Origin | None) -> list[Any]:
    """launch_ros's log line for one answer, and the loaded node counted in the launch."""
    node_name = response.full_node_name or request.node_name
    if not response.success:
        return [LogMessage('ERROR', f"Failed to load node '{node_name}' of type '{request.plugin_name}' in "
                                    f"container '{target}': {response.error_message}", origin, _LOGGER)]
    def count() -> None:   # on the supervisor's thread, which owns the context
        context.node_names[node_name] += 1
    return [CallEffect(f'count node {node_name}', count, origin),
            LogMessage('INFO', f"Loaded node '{response.full_node_name}' in container '{target}'", origin, _LOGGER)]
