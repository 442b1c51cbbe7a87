"""What a student sees on the terminal of TurtleBot3's navigation launch (issue 39), started as
the course prints it:
    zros launch turtlebot3_navigation2 navigation2.launch.py use_sim_time:=True map:=$HOME/map.yaml
Start-up shows the lines that matter (the managers bringing the stack up, AMCL asking for an
initial pose) without a warning per tf2 Buffer or the list of unused Nav2 parameters; Ctrl-C
stops everything quietly, with no node reported as failed. The view is left out (`rviz:=false`):
it has nothing to say on the terminal, and 2 cores are shared."""
from __future__ import annotations

import os
import shutil
import signal
import sys
from typing import Any

import pytest

from conftest import REPO, wait_until

ACTIVE = 'Managed nodes are active'
NO_POSE = 'No initial pose yet'


@pytest.fixture(scope='module')
def navigation(module_spawn: Any, tmp_path_factory: Any) -> Any:
    """The launch, with both lifecycle managers done and AMCL waiting for a pose."""
    home = tmp_path_factory.mktemp('home')
    for name in ('map.yaml', 'map.pgm'):       # the map the student saved in $HOME
        shutil.copy(REPO / 'nodes' / 'turtlebot3_navigation2' / 'map' / name, home / name)
    launch = module_spawn.command(sys.executable, '-m', 'zros', 'launch', 'turtlebot3_navigation2',
                                  'navigation2.launch.py', 'use_sim_time:=True', f'map:={home / "map.yaml"}',
                                  'rviz:=false', name='navigation2')
    launch.wait_for_output(NO_POSE, timeout=120)
    wait_until(lambda: launch.output().count(ACTIVE) == 2, 60,
               message=lambda: f'both lifecycle managers active\n{launch.output()[-3000:]}')
    return launch


def test_start_up_shows_the_useful_lines_only(navigation: Any) -> None:
    out = navigation.output()
    assert NO_POSE in out and '[lifecycle_manager_navigation]: ' + ACTIVE in out, out
    assert 'is already served by' not in out, out            # one per tf2 Buffer before
    assert 'Parameters zros does not use' not in out, out    # DEBUG now
    warnings = [line for line in out.splitlines() if '[WARN]' in line or '[ERROR]' in line]
    assert warnings and all(f'[amcl]: {NO_POSE}' in line for line in warnings), out  # the one that matters


def test_ctrl_c_stops_the_stack_without_failures(navigation: Any) -> None:
    """Ctrl-C reaches the launch's process group; the launch signals every node at once, so
    servers vanish while their lifecycle manager is stopping too: not a failure."""
    before = len(navigation.output())
    os.killpg(navigation.pid, signal.SIGINT)
    code = navigation.wait(5)
    stop = navigation.output()[before:]
    assert code == 0, stop
    assert 'user interrupted with ctrl-c (SIGINT)' in stop, stop
    for bad in ('CRITICAL', '[ERROR]', 'Failed to change state', 'Traceback', 'has died'):
        assert bad not in stop, stop
    assert stop.count('process has finished cleanly') == 9, stop
