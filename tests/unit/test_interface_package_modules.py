"""Python modules shipped beside interface files, and the test_msgs fixtures that use it."""
from __future__ import annotations

import importlib
import sys
from pathlib import Path

import pytest

UPSTREAM_INTERFACES = Path(__file__).resolve().parents[2] / 'benchmarks' / 'upstream_interfaces'


def test_a_module_beside_the_interface_files_imports_under_the_package(tmp_path: Path, monkeypatch: pytest.MonkeyPatch):
    package = tmp_path / 'zros_probe_pkg'
    (package / 'msg').mkdir(parents=True)
    (package / 'msg' / 'Probe.msg').write_text('int32 value\n')
    (package / 'helpers.py').write_text('from interfaces.zros_probe_pkg.msg import Probe\n'
                                        'def make():\n    return Probe(value=7)\n')
    monkeypatch.setenv('ZROS_INTERFACE_PATH', str(tmp_path))
    try:
        helpers = importlib.import_module('interfaces.zros_probe_pkg.helpers')
        assert helpers.make().value == 7
    finally:
        for name in [n for n in sys.modules if n.startswith('interfaces.zros_probe_pkg')]:
            del sys.modules[name]


def test_every_test_msgs_fixture_round_trips_through_the_message_codec(monkeypatch: pytest.MonkeyPatch):
    from zros.import_hook import install, uninstall
    from zros.message import deserialize, serialize
    monkeypatch.setenv('ZROS_INTERFACE_PATH', str(UPSTREAM_INTERFACES))
    install()
    try:
        fixtures = importlib.import_module('test_msgs.message_fixtures')
        for name in ('Arrays', 'BasicTypes', 'BoundedSequences', 'Builtins', 'Constants', 'Defaults', 'Empty',
                     'MultiNested', 'Nested', 'Strings', 'UnboundedSequences', 'WStrings'):
            samples = fixtures.get_test_msg(name)
            assert samples and all(type(m)._TYPE == f'test_msgs/msg/{name}' for m in samples)
            assert all(deserialize(serialize(m), type(m)) == m for m in samples)
    finally:
        uninstall()
        for name in [n for n in sys.modules if n.split('.')[0] == 'test_msgs' or n.startswith('interfaces.test_msgs')]:
            del sys.modules[name]
