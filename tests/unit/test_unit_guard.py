"""The unit tier's guard (tests/unit/conftest.py): a unit test that starts a process or opens a
Zenoh session fails with the reason, and a test marked `session` is let through."""
from __future__ import annotations

import subprocess
import sys

import pytest
import zenoh

# Taken at import, before the guard patches them for a test.
ZENOH_OPEN, POPEN_INIT = zenoh.open, subprocess.Popen.__init__


def test_a_unit_test_cannot_start_a_process():
    with pytest.raises(pytest.fail.Exception, match='a unit test started the process'):
        subprocess.run([sys.executable, '-c', 'pass'], timeout=10)


def test_a_unit_test_cannot_open_a_zenoh_session():
    with pytest.raises(pytest.fail.Exception, match='a unit test opened a Zenoh session; move it to tests/integration'):
        zenoh.open(zenoh.Config())


@pytest.mark.session
def test_a_test_marked_session_keeps_zenoh_and_subprocess():
    assert zenoh.open is ZENOH_OPEN and subprocess.Popen.__init__ is POPEN_INIT
