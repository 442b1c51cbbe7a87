"""Bridges between the zros graph and the tools ROS users open outside ROS: Foxglove
(`foxglove_bridge`), and web pages built on roslib (`rosbridge_server rosbridge_websocket`); see
docs/web-tools.md.

Each bridge is a plain class driven by a zros node, kept apart from the thin executable in
`nodes/` that reads its parameters, as Nav2 keeps its algorithms apart from its nodes.
"""
from __future__ import annotations

__all__: list[str] = []
