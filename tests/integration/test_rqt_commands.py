"""The rqt commands serve their page (the pages' content: tests/unit/test_rqt.py)."""
from __future__ import annotations

import sys
import urllib.request

import pytest


@pytest.mark.parametrize('command', [('run', 'rqt_plot', 'rqt_plot', '/turtle1/pose/x:y'), ('rqt', '--page', 'graph')])
def test_rqt_commands_serve_the_page(spawn, command):
    child = spawn(sys.executable, '-m', 'zros.cli.main', *command, '--port', '0', name='rqt')
    text = child.wait_for_output('http://127.0.0.1:', 30)
    url = 'http://127.0.0.1:' + text.split('http://127.0.0.1:', 1)[1].split()[0].rstrip('/') + '/'
    with urllib.request.urlopen(url, timeout=10) as response:
        assert response.status == 200 and b'<html' in response.read().lower()
