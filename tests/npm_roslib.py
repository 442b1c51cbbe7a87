"""roslib from npm for the tests that play a web client (and for the example page's screenshot).

The npm packages are installed once into a cache directory shared by test runs (under a lock),
never into the repository; a test that needs them is skipped, with the reason, when node or npm
is missing or the install fails (no registry reachable).
"""
from __future__ import annotations

import fcntl
import json
import os
import shutil
import subprocess
from pathlib import Path

import pytest

__all__ = ['CACHE', 'PACKAGES', 'roslib_modules', 'run_node']

CACHE = Path(os.environ.get('ZROS_TEST_NPM_CACHE', Path.home() / '.cache' / 'zros-test-npm-roslib'))
#: roslib 2 runs under node with `ws` as its WebSocket; both pinned so a run is repeatable.
PACKAGES = {'roslib': '2.1.0', 'ws': '8.23.0'}


def roslib_modules() -> Path:
    """The node_modules folder holding roslib (installed on first use); skips the test without it."""
    node, npm = shutil.which('node'), shutil.which('npm')
    if not node or not npm:
        pytest.skip('node and npm are needed for the roslib client (apt-get install nodejs npm)')
    CACHE.mkdir(parents=True, exist_ok=True)
    modules = CACHE / 'node_modules'
    with open(CACHE / '.lock', 'w') as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        installed = modules / 'roslib' / 'package.json'
        if installed.is_file() and json.loads(installed.read_text()).get('version') == PACKAGES['roslib']:
            return modules
        (CACHE / 'package.json').write_text(json.dumps(
            {'name': 'zros-test-roslib', 'private': True, 'dependencies': PACKAGES}, indent=2))
        try:
            result = subprocess.run([npm, 'install', '--no-audit', '--no-fund'], cwd=CACHE, capture_output=True,
                                    text=True, timeout=300)
        except subprocess.TimeoutExpired:
            pytest.skip('npm install of roslib timed out')
        if result.returncode != 0 or not installed.is_file():
            pytest.skip(f'npm install of roslib failed: {(result.stderr or result.stdout).strip()[-300:]}')
    return modules


def run_node(script: str, *args: str, timeout: float) -> subprocess.CompletedProcess:
    """Run an ES module under node; `ROSLIB` in its text is the file URL of roslib's module."""
    modules = roslib_modules()
    path = CACHE / f'client-{os.getpid()}-{abs(hash(script))}.mjs'
    path.write_text(script.replace('ROSLIB', (modules / 'roslib' / 'dist' / 'RosLib.js').as_uri()))
    try:
        return subprocess.run(['node', str(path), *args], capture_output=True, text=True, timeout=timeout)
    finally:
        path.unlink(missing_ok=True)
