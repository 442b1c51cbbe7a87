"""launch_ros.utilities: helpers launch_ros's actions and user code share for namespaces,
remap rules, node parameters and duplicate node names, on zros's launch model."""
from __future__ import annotations

from zros.launch_ros.utilities.namespace_utils import (is_namespace_absolute, is_root_namespace,
                                                       make_namespace_absolute, prefix_namespace)
from zros.launch_ros.utilities.parameters import evaluate_parameters, normalize_parameters
from zros.launch_ros.utilities.normalize_remap_rule import normalize_remap_rule, normalize_remap_rules
from zros.launch_ros.utilities.track_node_names import add_node_name, get_node_name_count

__all__ = ['add_node_name', 'get_node_name_count', 'is_namespace_absolute', 'is_root_namespace',
           'make_namespace_absolute', 'prefix_namespace', 'normalize_parameters', 'evaluate_parameters', 'normalize_remap_rule', 'normalize_remap_rules']
