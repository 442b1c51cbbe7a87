"""`pip install zros` without extras: the core runs a talker and a listener, every CLI verb
loads, and a tool whose extra is missing says which to install in one line.

The extras' packages are installed in the test venv, so each child process gets a
sitecustomize (through PYTHONPATH, children of children included) whose meta-path finder
refuses them, as an interpreter without them would.
"""
from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from conftest import REPO, assert_clean_failure, run_cli
from zros.extras import EXTRA_OF

BLOCKER = '''
import sys


class _NotInstalled:
    """The extras' packages are not installed here (tests/test_extras.py)."""

    def find_spec(self, name, path=None, target=None):
        if name.split('.')[0] in {blocked!r}:
            raise ModuleNotFoundError(f"No module named {{name!r}}", name=name)
        return None


sys.meta_path.insert(0, _NotInstalled())
'''


@pytest.fixture
def core_only(tmp_path: Path, domain: int, monkeypatch: pytest.MonkeyPatch) -> dict[str, str]:
    """The environment of a core-only install, for this test and the processes it starts."""
    site = tmp_path / 'core_only_site'
    site.mkdir()
    (site / 'sitecustomize.py').write_text(BLOCKER.format(blocked=set(EXTRA_OF)))
    monkeypatch.setenv('PYTHONPATH', os.pathsep.join(filter(None, [str(site), os.environ.get('PYTHONPATH')])))
    return dict(os.environ)


@pytest.mark.parametrize('package', sorted(EXTRA_OF))
def test_the_extras_packages_are_blocked(core_only, package):
    result = subprocess.run([sys.executable, '-c', f'import {package}'], env=core_only, cwd=REPO,
                            capture_output=True, text=True, timeout=60)
    assert result.returncode != 0 and 'ModuleNotFoundError' in result.stderr, result


def test_talker_and_listener_talk_without_the_extras(core_only, spawn):
    talker = spawn.node('demo_nodes', 'talker')
    listener = spawn.node('demo_nodes', 'listener')
    listener.wait_for_output('I heard: [Hello World: ', timeout=30)
    assert "Publishing: 'Hello World: " in talker.output()


def test_every_cli_verb_loads_without_the_extras(core_only):
    result = run_cli('--help', env=core_only)
    assert result.returncode == 0 and 'bag' in result.stdout and 'view' in result.stdout, result
    assert 'demo_nodes talker' in run_cli('pkg', 'executables', 'demo_nodes', env=core_only).stdout


@pytest.mark.parametrize('argv, extra, what', [
    (('run', 'turtlesim', 'turtlesim_node'), 'sim', 'zros run turtlesim turtlesim_node'),
    (('view',), 'view', 'zros view'),
    (('run', 'nav2_amcl', 'amcl'), 'nav', 'zros run nav2_amcl amcl'),
])
def test_a_missing_extra_is_one_line_naming_it(core_only, argv, extra, what):
    assert_clean_failure(run_cli(*argv, env=core_only, timeout=30),
                         f"{what} needs the '{extra}' extra: pip install 'zros[{extra}]'")
