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
