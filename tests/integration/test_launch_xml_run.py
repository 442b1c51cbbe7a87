"""XML launch files run by `zros launch` (their parsing and plans: tests/unit/test_launch_xml.py)."""
from __future__ import annotations

import re
from pathlib import Path

from conftest import assert_clean_failure, run_cli
from unit.test_launch_parse import write  # noqa: F401 - the fixture
from integration.test_launch_run import Launch


def test_bad_xml_through_the_cli_is_one_line(write):
    path = write('bad.launch.xml', '<launch>\n  <node pkg="demo_nodes" exec="talker" colour="red"/>\n</launch>\n')
    line = assert_clean_failure(run_cli('launch', str(path), '--print'), f"{path}:2: node: colour: unknown attribute")
    assert line.startswith(f"{path}:2: node: colour: unknown attribute 'colour' of `node` (known: args, cwd,"), line


def test_talker_and_listener_from_xml_talk(tmp_path: Path, domain: int):
    path = tmp_path / 'chat.launch.xml'
    path.write_text('<launch>\n'
                    '  <arg name="topic" default="xml_chatter"/>\n'
                    '  <node pkg="demo_nodes" exec="talker" output="screen">\n'
                    '    <remap from="chatter" to="$(var topic)"/>\n'
                    '  </node>\n'
                    '  <node pkg="demo_nodes" exec="listener" name="ears" output="screen">\n'
                    '    <remap from="chatter" to="$(var topic)"/>\n'
                    '  </node>\n'
                    '</launch>\n')
    run = Launch(path, [], tmp_path)
    try:
        out = run.wait_for("[ears]: I heard: [Hello World:", timeout=30)
        assert re.search(r"\[talker-1\] \[INFO\] \[[\d.]+\] \[talker\]: Publishing: 'Hello World: \d+'", out), out
        assert re.search(r"\[listener-2\] \[INFO\] \[[\d.]+\] \[ears\]: I heard: \[Hello World: \d+\]", out), out
    finally:
        run.kill()
