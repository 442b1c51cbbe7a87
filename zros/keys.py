"""Zenoh key expressions for zros entities: the only place they are built (protocol v1).

    zros/<domain>/t/<topic>          topic data            (name without its leading '/')
    zros/<domain>/s/<service>        service queryable
    @zros/v1/<domain>/...            liveliness tokens (see zros.graph)

Names reaching here are validated ROS names (letters, digits, '_', '/'), so no Zenoh wildcard
can appear in a key. docs/protocol.md is the user-facing description of this layout.
"""
from __future__ import annotations

__all__ = ['PROTOCOL_VERSION', 'topic_key', 'service_key', 'liveliness_prefix', 'mangle', 'unmangle']

PROTOCOL_VERSION = 1


def topic_key(domain: int, fq_name: str) -> str:
    return f'zros/{domain}/t{fq_name}'


def service_key(domain: int, fq_name: str) -> str:
    return f'zros/{domain}/s{fq_name}'


def liveliness_prefix(domain: int) -> str:
    return f'@zros/v{PROTOCOL_VERSION}/{domain}'


def mangle(text: str) -> str:
    """Fold a name or type into one key chunk: '/' becomes '%', and '' (root) becomes '%'."""
    return text.replace('/', '%') or '%'


def unmangle(chunk: str) -> str:
    return chunk.replace('%', '/')
