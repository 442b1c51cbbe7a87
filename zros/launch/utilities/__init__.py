"""launch.utilities: the helpers launch's actions and user code share to check, normalize and
evaluate arguments (typed values are in `type_utils`).

They work on zros's own Substitution classes and LaunchContext, so what a launch file built
with them resolves as `zros launch` resolves it.
"""
from __future__ import annotations

from zros.launch.utilities.class_tools_impl import is_a, is_a_subclass, isclassinstance
from zros.launch.utilities.ensure_argument_type_impl import ensure_argument_type
from zros.launch.utilities.entities import normalize_to_list_of_entities, visit_all_entities_and_collect_futures
from zros.launch.utilities.normalize_to_list_of_substitutions_impl import normalize_to_list_of_substitutions
from zros.launch.utilities.perform_substitutions_impl import perform_substitutions
from zros.launch.utilities.signal_management import AsyncSafeSignalManager

__all__ = ['is_a', 'is_a_subclass', 'isclassinstance', 'ensure_argument_type', 'normalize_to_list_of_substitutions',
           'perform_substitutions', 'AsyncSafeSignalManager', 'normalize_to_list_of_entities',
           'visit_all_entities_and_collect_futures']
