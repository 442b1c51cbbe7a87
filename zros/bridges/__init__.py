"""Bridges from the zros graph to the tools ROS users open outside ROS (Foxglove, web pages).

Each bridge is a plain class driven by a zros node, kept apart from the thin executable in
`nodes/` that reads its parameters, as Nav2 keeps its algorithms apart from its nodes.
"""
from __future__ import annotations

__all__: list[str] = []
