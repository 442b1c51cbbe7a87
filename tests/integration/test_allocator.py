"""zros.allocator: a zros process reuses the memory of large freed blocks instead of faulting in
fresh pages for every large message (the cost that held 1 MB images over TCP to a third of
their rate)."""
from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]

# After zros.init, copy 1 MiB blocks as a large message's path does (two live at a time, then
# both freed) and count the page faults per round.
_PROGRAM = '''
import resource
import zros
import zros.allocator
with zros.init(args=['allocator_probe']):
    def rounds(count):
        for _ in range(count):
            first = bytearray(1 << 20)
            second = bytes(first)
            del first, second
    rounds(20)
    before = resource.getrusage(resource.RUSAGE_SELF).ru_minflt
    rounds(200)
    faults = resource.getrusage(resource.RUSAGE_SELF).ru_minflt - before
    print(zros.allocator._tuned, faults / 200)
'''


def _probe(**env: str) -> tuple[bool, float]:
    result = subprocess.run([sys.executable, '-c', _PROGRAM], capture_output=True, text=True, timeout=60, cwd=REPO,
                            env={**os.environ, **env})
    assert result.returncode == 0, result.stderr[-2000:]
    tuned, faults = result.stdout.split()
    return tuned == 'True', float(faults)


@pytest.mark.skipif(not hasattr(os, 'confstr') or not os.confstr('CS_GNU_LIBC_VERSION').startswith('glibc'),
                    reason='the thresholds are glibc settings')
def test_large_blocks_are_reused_instead_of_faulted_in_again(domain):
    tuned, faults = _probe()
    assert tuned
    assert faults < 8, f'{faults} page faults per 2 MiB round: freed blocks went back to the kernel'
    # The same program with glibc's defaults, for scale: the pages come back fresh every round.
    tuned, faults_by_default = _probe(ZROS_MALLOC_TUNING='0')
    assert not tuned
    assert faults_by_default > 100, faults_by_default


def test_a_user_setting_of_malloc_is_left_alone(domain):
    tuned, _ = _probe(MALLOC_TRIM_THRESHOLD_='1048576')
    assert not tuned


# After zros.init, eight threads allocate at once; glibc's malloc_stats lists one "Arena N:" per
# heap on stderr.
_ARENAS = '''
import ctypes, sys, threading
import zros
with zros.init(args=['arena_probe']):
    start = threading.Barrier(8)
    def work():
        start.wait()
        blocks = [bytearray(4096) for _ in range(200)]
        del blocks
    threads = [threading.Thread(target=work) for _ in range(8)]
    for t in threads: t.start()
    for t in threads: t.join()
    sys.stderr.flush()
    ctypes.CDLL(None).malloc_stats()
'''


def _arenas(**env: str) -> int:
    result = subprocess.run([sys.executable, '-c', _ARENAS], capture_output=True, text=True, timeout=60, cwd=REPO,
                            env={**os.environ, **env})
    assert result.returncode == 0, result.stderr[-2000:]
    return sum(line.startswith('Arena ') for line in result.stderr.splitlines())


@pytest.mark.skipif(not hasattr(os, 'confstr') or not os.confstr('CS_GNU_LIBC_VERSION').startswith('glibc'),
                    reason='the arenas are glibc heaps')
def test_the_threads_of_a_zros_process_share_arena_max_heaps(domain):
    """A heap per thread kept each thread's freed memory to itself: a navigation server's
    memory grew for as long as it ran (issue 36's soak)."""
    from zros.allocator import ARENA_MAX
    assert _arenas() <= ARENA_MAX
    assert _arenas(ZROS_MALLOC_TUNING='0') > ARENA_MAX    # glibc's default, for scale
