"""`composition::Listener`: the composition demo's listener component, demo_nodes' listener."""
from nodes.demo_nodes.listener import main

__all__ = ['main']
