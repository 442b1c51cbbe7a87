"""How many wait-set entities an action server or client stands for (rclpy's NumberOfEntities).

rclpy's executors size their wait sets from these counts; zros's executors do not wait on
handles, so the counts only describe what an action is built from, for code that inspects it.
"""
from __future__ import annotations

from collections import namedtuple

__all__ = ['NumberOfEntities']

#: Counts of the entities of one kind of waitable; each is zero unless given.
NumberOfEntities = namedtuple('NumberOfEntities', ['num_subscriptions', 'num_guard_conditions', 'num_timers',
                                                   'num_clients', 'num_services', 'num_events'],
                              defaults=(0, 0, 0, 0, 0, 0))
