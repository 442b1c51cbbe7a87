"""`composition::Talker`: the composition demo's talker component, demo_nodes' talker."""
from nodes.demo_nodes.talker import main

__all__ = ['main']
