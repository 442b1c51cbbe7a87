"""Shared memory for large payloads between processes of one machine.

Zenoh moves a put of 3 KB or more through a shared-memory pool when the publisher and the
subscriber run on one machine (its "transport optimization"); zros sizes that pool with
`ZROS_SHM_POOL_SIZE` (default 64 MiB: room for several camera frames in flight, where Zenoh's
16 MiB holds one 8 MB message; `0` turns shared memory off). Nothing changes across machines:
Zenoh copies a shared-memory payload into the network message for a peer that cannot map it.

zros does not allocate from a pool of its own. A buffer of an explicit `ShmProvider` is free to
be garbage-collected as soon as the publisher has sent it, before a slow subscriber has mapped
it: when the pool ran full under back-pressure, the collection reclaimed buffers still waiting
in the socket and the subscriber lost them from a reliable stream. Zenoh's own pool does not.
"""
from __future__ import annotations

import os
from typing import Any

from zros.wire import parse_size

__all__ = ['DEFAULT_POOL_SIZE', 'pool_size', 'zenoh_settings']

DEFAULT_POOL_SIZE = 64 << 20


def pool_size() -> int:
    """Bytes of each shared-memory pool (ZROS_SHM_POOL_SIZE; 0: no shared memory)."""
    text = os.environ.get('ZROS_SHM_POOL_SIZE')
    return DEFAULT_POOL_SIZE if not text else parse_size(text, 'ZROS_SHM_POOL_SIZE')


def zenoh_settings() -> dict[str, Any]:
    """The Zenoh config entries that zros sets (where a ZROS_CONFIG file leaves them unset)."""
    size = pool_size()
    if size == 0:
        return {'transport/shared_memory/enabled': False}
    return {'transport/shared_memory/transport_optimization/pool_size': size}
