"""The C allocator's thresholds, set once per zros process so that large messages reuse memory.

glibc gives freed memory back to the kernel as soon as more than `M_TRIM_THRESHOLD` is free at
the top of a heap, and serves big blocks with mmap; both thresholds start at 128 KiB and grow
only as far as the blocks freed so far. Every large message is copied into fresh blocks (Zenoh
reassembling it, `to_bytes`, the decoded arrays), so with those defaults a subscriber of 1 MB
images over TCP mapped, zero-filled and unmapped fresh pages for each message: on the
benchmark machine its executor spent most of its CPU in page faults and delivered 350 - 420
messages a second; with the thresholds below, 1,000 - 1,400 at less CPU (docs/benchmarks.md).

zros keeps blocks under `MMAP_THRESHOLD` on the heap and up to `TRIM_THRESHOLD` of freed memory
per heap for reuse: that much memory stays with a process after a burst of large messages.
It also caps the heaps (arenas) at `ARENA_MAX`: glibc makes up to eight per core, one per thread
that allocates at the same moment as another, and each keeps its own freed memory. A navigation
server has a dozen threads (its executor's, Zenoh's) that take turns under the GIL, so they gain
little from their own heaps, and the memory freed in each was not reused by the others: the
process grew for as long as it ran (issue 36's soak; docs/benchmarks-history.md).

`ZROS_MALLOC_TUNING=0` keeps glibc's defaults, and so does a process whose environment already
sets glibc's own malloc settings. Other C libraries (musl, macOS) are left alone.
"""
from __future__ import annotations

import os

__all__ = ['ARENA_MAX', 'MMAP_THRESHOLD', 'TRIM_THRESHOLD', 'tune']

#: Blocks smaller than this come from the heap, not from mmap (glibc's own upper bound for its
#: moving threshold): a camera frame or a point cloud reuses freed memory.
MMAP_THRESHOLD = 32 << 20
#: Free memory a heap keeps at its top before giving it back to the kernel.
TRIM_THRESHOLD = 64 << 20
#: Heaps the threads of a process share (glibc's default is eight per core).
ARENA_MAX = 2

# glibc's mallopt parameter numbers (malloc.h).
_M_TRIM_THRESHOLD = -1
_M_MMAP_THRESHOLD = -3
_M_ARENA_MAX = -8
_USER_SETTINGS = ('MALLOC_TRIM_THRESHOLD_', 'MALLOC_MMAP_THRESHOLD_', 'MALLOC_TOP_PAD_', 'MALLOC_ARENA_MAX')

_tuned = False


def tune() -> bool:
    """Set the thresholds for this process (once; later calls do nothing). True when they are
    in effect, False where they do not apply or are turned off."""
    global _tuned
    if _tuned:
        return True
    if os.environ.get('ZROS_MALLOC_TUNING', '1').strip() == '0':
        return False
    if any(name in os.environ for name in _USER_SETTINGS) or 'glibc.malloc' in os.environ.get('GLIBC_TUNABLES', ''):
        return False   # the user tuned malloc already
    try:
        if not os.confstr('CS_GNU_LIBC_VERSION').startswith('glibc'):
            return False
    except (ValueError, OSError, AttributeError):
        return False
    import ctypes
    try:
        mallopt = ctypes.CDLL(None).mallopt
    except (OSError, AttributeError):
        return False
    # The mmap threshold first: setting either one stops glibc from moving both.
    _tuned = mallopt(_M_MMAP_THRESHOLD, MMAP_THRESHOLD) == 1 and mallopt(_M_TRIM_THRESHOLD, TRIM_THRESHOLD) == 1
    # Before the session's and the executor's threads start: a cap applies to heaps made after it.
    _tuned = _tuned and mallopt(_M_ARENA_MAX, ARENA_MAX) == 1
    return _tuned
