"""Shared memory for large payloads between processes of one machine.

Zenoh already moves a put of 3 KB or more through a shared-memory pool when the publisher and
the subscriber run on one machine (its "transport optimization"); zros sizes that pool with
`ZROS_SHM_POOL_SIZE` (default 64 MiB: room for several camera frames in flight, where Zenoh's
16 MiB holds one 8 MB message). For payloads of `SHM_THRESHOLD` bytes and more, zros writes the
encoded message straight into a buffer of its own pool, which saves the copy Zenoh would make
into its pool. Nothing changes across machines: Zenoh copies a shared-memory payload into the
network message for a peer that cannot map it, so a subscriber elsewhere receives it as usual.
When the pool is full, or shared memory is unavailable (a small /dev/shm), the payload goes the
ordinary way. `ZROS_SHM_POOL_SIZE=0` turns shared memory off.
"""
from __future__ import annotations

import os
import threading
from typing import Any

from zros.wire import parse_size

__all__ = ['SHM_THRESHOLD', 'DEFAULT_POOL_SIZE', 'pool_size', 'zenoh_settings', 'payload']

#: Payloads from this size on are written into zros's shared-memory pool.
SHM_THRESHOLD = 64 << 10
DEFAULT_POOL_SIZE = 64 << 20

_lock = threading.Lock()
_provider: Any = None
_unavailable = False


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


def _pool() -> Any:
    """The process's ShmProvider, made on first use; None when shared memory is off or cannot
    be set up here."""
    global _provider, _unavailable
    if _provider is not None or _unavailable:
        return _provider
    with _lock:
        if _provider is None and not _unavailable:
            size = pool_size()
            try:
                import zenoh.shm
                _provider = zenoh.shm.ShmProvider.default_backend(size) if size else None
            except Exception:  # noqa: BLE001 - no /dev/shm, too small, no SHM in this zenoh build
                _provider = None
            _unavailable = _provider is None
    return _provider


def payload(data: bytes) -> Any:
    """`data` to put on Zenoh: a shared-memory buffer holding it when it is large and the pool
    has room, else `data` itself."""
    if len(data) < SHM_THRESHOLD:
        return data
    provider = _pool()
    if provider is None:
        return data
    import zenoh
    import zenoh.shm
    try:
        buffer = provider.alloc(len(data), zenoh.shm.GarbageCollect())
    except zenoh.ZError:
        return data  # the pool is full of buffers that readers still hold
    buffer[0:len(data)] = data
    return zenoh.ZBytes(buffer)
