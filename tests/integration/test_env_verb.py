"""`zros env WS`: one eval makes a workspace's interfaces and nodes visible in a new shell."""
from __future__ import annotations

import os
import subprocess
import sys

from conftest import REPO, assert_clean_failure


def test_env_exports_a_colcon_style_workspace(tmp_path, zros_cli):
    src = tmp_path / 'ws' / 'src'
    (src / 'robot_interfaces' / 'msg').mkdir(parents=True)
    (src / 'robot_interfaces' / 'msg' / 'Battery.msg').write_text('float32 percent\nstring name\n')
    (src / 'my_pkg' / 'my_pkg').mkdir(parents=True)
    (src / 'my_pkg' / 'my_pkg' / 'hello.py').write_text('def main():\n    print("hello from my_pkg")\n')
    printed = zros_cli('env', str(tmp_path / 'ws'))
    assert printed.returncode == 0, printed
    assert printed.stdout.splitlines() == [f'export ZROS_INTERFACE_PATH={src}', f'export ZROS_NODE_PATH={src / "my_pkg"}']
    script = (f'eval "$({sys.executable} -m zros.cli.main env {tmp_path / "ws"})" && '
              f'{sys.executable} -m zros.cli.main run my_pkg hello && '
              f'{sys.executable} -m zros.cli.main interface show robot_interfaces/msg/Battery')
    env = {**os.environ, 'ZROS_NODE_PATH': '/already/there'}
    shell = subprocess.run(['bash', '-c', script], capture_output=True, text=True, timeout=60, cwd=REPO, env=env)
    assert shell.returncode == 0, shell
    assert shell.stdout.splitlines() == ['hello from my_pkg', 'float32 percent', 'string name'], shell
    kept = subprocess.run(['bash', '-c', f'eval "$({sys.executable} -m zros.cli.main env {tmp_path / "ws"})"; '
                           'echo "$ZROS_NODE_PATH"'], capture_output=True, text=True, timeout=30, cwd=REPO, env=env)
    assert kept.stdout.strip() == f'{src / "my_pkg"}:/already/there', kept
    assert_clean_failure(zros_cli('env', str(tmp_path / 'missing')), 'not a directory')
    (tmp_path / 'empty').mkdir()
    assert_clean_failure(zros_cli('env', str(tmp_path / 'empty')), 'no packages')
