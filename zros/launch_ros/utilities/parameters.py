"""launch_ros.utilities's `normalize_parameters` and `evaluate_parameters`, which zros keeps in
zros.launch.parameter_evaluation (the launch builds LoadNode requests with them)."""
from __future__ import annotations

from zros.launch.parameter_evaluation import evaluate_parameters, normalize_parameters

__all__ = ['normalize_parameters', 'evaluate_parameters']
