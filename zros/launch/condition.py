"""launch.condition: the module of the Condition base class (`from launch import condition`,
`condition.Condition(predicate=...)`), as launch lays it out; the conditions are zros.launch.conditions'."""
from zros.launch.conditions import Condition

__all__ = ['Condition']
