"""Bridges between the zros graph and tools that speak another protocol.

rosbridge (`rosbridge_server rosbridge_websocket`) gives web pages built on roslib the topics,
services, actions and parameters of a zros system over one WebSocket; see docs/web-tools.md.
"""
