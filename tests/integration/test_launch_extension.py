"""A launch extension: a package exposes a tag with `expose_action`, `zros launch` runs it from XML.

The package is declared the way ROS 2 packages declare one, under the
`launch.frontend.launch_extension` entry point group (here a bare `.dist-info` on PYTHONPATH),
and its module is written against `launch`, not `zros.launch`.
"""
from __future__ import annotations

import os
import textwrap
from pathlib import Path

from conftest import run_cli

EXTENSION = '''
from launch import Action
from launch.actions import LogInfo
from launch.frontend import expose_action


@expose_action('greet')
class Greet(Action):
    """<greet whom="..."/>: says hello to whom, by returning a LogInfo to run next."""

    def __init__(self, *, whom, **kwargs):
        super().__init__(**kwargs)
        self.whom = whom

    @classmethod
    def parse(cls, entity, parser):
        _, kwargs = super().parse(entity, parser)
        kwargs['whom'] = parser.parse_substitution(entity.get_attr('whom'))
        return cls, kwargs

    def execute(self, context):
        return [LogInfo(msg=['hello, ', *self.whom])]
'''


def _install_extension(root: Path) -> dict[str, str]:
    (root / 'greeting_ext.py').write_text(EXTENSION)
    info = root / 'greeting_ext-1.0.dist-info'
    info.mkdir()
    (info / 'METADATA').write_text('Metadata-Version: 2.1\nName: greeting_ext\nVersion: 1.0\n')
    (info / 'entry_points.txt').write_text('[launch.frontend.launch_extension]\ngreeting_ext = greeting_ext\n')
    return {**os.environ, 'PYTHONPATH': os.pathsep.join(filter(None, [str(root), os.environ.get('PYTHONPATH')]))}


def test_an_exposed_tag_runs_under_zros_launch(tmp_path: Path):
    env = _install_extension(tmp_path)
    path = tmp_path / 'greet.launch.xml'
    path.write_text(textwrap.dedent('''\
        <launch>
          <arg name="who" default="nobody"/>
          <greet whom="$(var who)"/>
          <greet whom="twice" if="false"/>
        </launch>
        '''))
    result = run_cli('launch', str(path), 'who:=world', env=env, timeout=60)
    assert result.returncode == 0, result
    output = result.stdout + result.stderr
    assert output.count('[launch.user]: hello, ') == 1, result
    assert '[launch.user]: hello, world' in output, result


def test_an_exposed_tag_checks_its_attributes(tmp_path: Path):
    env = _install_extension(tmp_path)
    path = tmp_path / 'bad.launch.xml'
    path.write_text('<launch>\n  <greet whom="x" loudly="yes"/>\n</launch>\n')
    result = run_cli('launch', str(path), '--print', env=env, timeout=60)
    assert result.returncode != 0, result
    assert f"{path}:2: greet: loudly: unknown attribute 'loudly' of `greet`" in result.stderr, result
