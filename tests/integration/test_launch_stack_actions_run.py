"""The stack actions in a Python launch file run by `zros launch`: what a process started
inside a pushed scope sees, and what the file sees after the pops (pure checks of the same
actions: tests/unit/test_launch_stack_actions.py)."""
from __future__ import annotations

import sys
from pathlib import Path

from conftest import run_cli
from unit.test_launch_parse import write  # noqa: F401 - the fixture

STACKED = f'''
from launch import LaunchDescription
from launch.actions import (ExecuteProcess, LogInfo, PopEnvironment, PopLaunchConfigurations, PushEnvironment,
                            PushLaunchConfigurations, ResetEnvironment, SetEnvironmentVariable,
                            SetLaunchConfiguration, UnsetEnvironmentVariable, UnsetLaunchConfiguration)
from launch.substitutions import EnvironmentVariable, LaunchConfiguration

SHOW = "import os; print('SEEN', os.environ.get('STACK_VAR', '-'), os.environ.get('STACK_OUTER', '-'))"


def generate_launch_description():
    return LaunchDescription([
        SetEnvironmentVariable('STACK_OUTER', 'outer'),
        SetLaunchConfiguration('robot', 'r1'),
        PushLaunchConfigurations(),
        PushEnvironment(),
        SetEnvironmentVariable('STACK_VAR', 'inner'),
        SetLaunchConfiguration('robot', 'r2'),
        ExecuteProcess(cmd=[{sys.executable!r}, '-c', SHOW], name='inside', output='screen'),
        ResetEnvironment(),
        ExecuteProcess(cmd=[{sys.executable!r}, '-c', SHOW], name='reset', output='screen'),
        LogInfo(msg=['INSIDE robot=', LaunchConfiguration('robot')]),
        PopEnvironment(),
        PopLaunchConfigurations(),
        LogInfo(msg=['AFTER robot=', LaunchConfiguration('robot'), ' outer=',
                     EnvironmentVariable('STACK_OUTER', default_value='-')]),
        UnsetLaunchConfiguration('robot'),
        UnsetEnvironmentVariable('STACK_OUTER'),
        LogInfo(msg=['UNSET robot=', LaunchConfiguration('robot', default='none'), ' outer=',
                     EnvironmentVariable('STACK_OUTER', default_value='none')]),
    ])
'''


def test_pushed_scopes_reach_processes_and_end_at_the_pops(write, tmp_path: Path):
    path = write('stacked.launch.py', STACKED)
    result = run_cli('launch', str(path), '--log-dir', str(tmp_path / 'log'), timeout=60)
    assert result.returncode == 0, result
    out = result.stdout
    lines = {name: next((line for line in out.splitlines() if f'[{name}' in line and 'SEEN' in line), '')
             for name in ('inside', 'reset')}
    assert lines['inside'].endswith('SEEN inner outer'), out
    assert lines['reset'].endswith('SEEN - -'), out           # back to the environment the launch started in
    assert 'INSIDE robot=r2' in out and 'AFTER robot=r1 outer=outer' in out, out
    assert 'UNSET robot=none outer=none' in out, out
