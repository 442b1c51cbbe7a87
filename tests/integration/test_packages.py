"""Your own package with no build step: `zros pkg create` output installed in a fresh venv,
its node, custom message, launch file and generated test run; `zros pkg list / executables /
prefix`, `zros interface package` and the package index."""
from __future__ import annotations

import subprocess
from pathlib import Path

import pytest

from conftest import REPO, assert_clean_failure, run_cli
from zros.ament_index_python import packages
from zros.ament_index_python.packages import (PackageNotFoundError, get_package_prefix, get_package_share_directory,
                                              get_packages_with_prefixes)

NUM_CHECK = '''
import zros
from zros.node import Node
from zros.testing import spin_until

from interfaces.demo_pkg.msg import Num

with zros.init([]):
    node = Node('num_check')
    received = []
    node.create_subscription(Num, 'numbers', received.append, 10)
    publisher = node.create_publisher(Num, 'numbers', 10)

    def publish_until_received():
        publisher.publish(Num(num=41, label='custom'))
        return received
    spin_until(node, publish_until_received, 10.0, message='a Num')
    print('RECEIVED', type(received[0]).__name__, received[0].num, received[0].label)
'''


def _run(argv: list, *, cwd: Path, timeout: float = 120.0) -> subprocess.CompletedProcess:
    result = subprocess.run([str(a) for a in argv], cwd=cwd, capture_output=True, text=True, timeout=timeout,
                            stdin=subprocess.DEVNULL)
    assert result.returncode == 0, f'{argv}: exit {result.returncode}\n{result.stdout}\n{result.stderr}'
    return result


def test_pkg_create_output_installs_and_runs_in_a_fresh_venv(domain: int, tmp_path: Path, fresh_venv: Path):
    created = run_cli('pkg', 'create', 'demo_pkg', '--node-name', 'demo_node', '--dependencies', 'geometry_msgs',
                      '--destination-directory', tmp_path)
    assert created.returncode == 0, created
    assert 'package name: demo_pkg' in created.stdout and "dependencies: ['std_msgs', 'geometry_msgs']" in created.stdout
    source = tmp_path / 'demo_pkg'
    (source / 'demo_pkg' / 'msg' / 'Num.msg').write_text('int64 num\nstring label\n')
    # A regular (not editable) install: what is used comes from site-packages, not from source.
    _run([fresh_venv, '-m', 'pip', 'install', '-q', '--no-deps', source], cwd=tmp_path, timeout=300)
    elsewhere = tmp_path / 'elsewhere'
    elsewhere.mkdir()
    zros = [fresh_venv, '-m', 'zros']
    assert _run([*zros, 'pkg', 'executables', 'demo_pkg'], cwd=elsewhere).stdout == 'demo_pkg demo_node\n'
    assert _run([*zros, 'interface', 'package', 'demo_pkg'], cwd=elsewhere).stdout == 'demo_pkg/msg/Num\n'
    share = _run([*zros, 'pkg', 'prefix', '--share', 'demo_pkg'], cwd=elsewhere).stdout.strip()
    assert share.endswith('site-packages/demo_pkg') and (Path(share) / 'msg' / 'Num.msg').is_file()
    plan = _run([*zros, 'launch', 'demo_pkg', 'demo_pkg.launch.py', '--print', '--log-dir', tmp_path / 'log'],
                cwd=elsewhere).stdout
    assert f'launch file: {share}/launch/demo_pkg.launch.py' in plan and 'zros run demo_pkg demo_node' in plan
    (elsewhere / 'num_check.py').write_text(NUM_CHECK)
    assert 'RECEIVED Num 41 custom' in _run([fresh_venv, 'num_check.py'], cwd=elsewhere).stdout
    node = subprocess.Popen([*map(str, zros), 'run', 'demo_pkg', 'demo_node'], cwd=elsewhere, stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, text=True, start_new_session=True)
    try:
        echoed = run_cli('topic', 'echo', '/chatter', 'std_msgs/msg/String', '--once', '--timeout', '20', timeout=30)
        assert "data: 'Hello from demo_pkg: " in echoed.stdout or 'data: Hello from demo_pkg: ' in echoed.stdout, echoed
    finally:
        node.send_signal(2)
        node.wait(timeout=10)
    # The package's own test, with zros.testing's fixtures (its isolated domain, not ours).
    tested = _run([fresh_venv, '-m', 'pytest', '-q', '-p', 'no:cacheprovider'], cwd=source, timeout=180)
    assert '2 passed' in tested.stdout, tested.stdout


def test_pkg_create_refuses_bad_names_and_existing_folders(tmp_path: Path):
    assert_clean_failure(run_cli('pkg', 'create', 'My-Pkg', '--destination-directory', tmp_path),
                         "package name 'My-Pkg' must start with a lowercase letter")
    assert run_cli('pkg', 'create', 'lonely', '--destination-directory', tmp_path).returncode == 0
    assert (tmp_path / 'lonely' / 'lonely' / 'launch' / 'lonely.launch.py').is_file()
    assert (tmp_path / 'lonely' / 'tests' / 'test_package.py').is_file()
    assert_clean_failure(run_cli('pkg', 'create', 'lonely', '--destination-directory', tmp_path),
                         'Aborted: a folder named lonely already exists')


def test_pkg_verbs_find_a_package_on_the_node_path(tmp_path: Path, monkeypatch: pytest.MonkeyPatch):
    package = tmp_path / 'ws' / 'my_robot'
    (package / 'msg').mkdir(parents=True)
    (package / 'launch').mkdir()
    (package / 'drive.py').write_text('def main():\n    print("driving")\n')
    (package / 'msg' / 'Wheel.msg').write_text('float64 speed\n')
    monkeypatch.setenv('ZROS_NODE_PATH', str(tmp_path / 'ws'))
    assert 'my_robot' in run_cli('pkg', 'list').stdout.split()
    assert run_cli('pkg', 'executables', 'my_robot').stdout == 'my_robot drive\n'
    assert 'demo_nodes talker\n' in run_cli('pkg', 'executables').stdout
    assert run_cli('pkg', 'executables', 'my_robot', '--full-path').stdout == f'{package / "drive.py"}\n'
    assert run_cli('pkg', 'prefix', 'my_robot').stdout == f'{tmp_path / "ws"}\n'
    assert run_cli('pkg', 'prefix', 'my_robot', '--share').stdout == f'{package}\n'
    assert run_cli('interface', 'package', 'my_robot').stdout == 'my_robot/msg/Wheel\n'
    assert run_cli('run', 'my_robot', 'drive').stdout == 'driving\n'
    assert_clean_failure(run_cli('pkg', 'prefix', 'nope'), 'Package not found')
    assert_clean_failure(run_cli('pkg', 'executables', 'nope'), "Package 'nope' not found")


def test_a_created_project_on_the_node_path_is_its_packages_only(tmp_path: Path, monkeypatch: pytest.MonkeyPatch):
    """The project folder of `zros pkg create` on ZROS_NODE_PATH (as its README says) holds one
    package: its `tests/` folder is no package for `zros pkg`, `zros run` or the index."""
    assert run_cli('pkg', 'create', 'my_pkg', '--node-name', 'my_node', '--destination-directory',
                   tmp_path).returncode == 0
    project = tmp_path / 'my_pkg'
    (project / 'docs').mkdir()
    monkeypatch.setenv('ZROS_NODE_PATH', str(project))
    listed = run_cli('pkg', 'list').stdout.split()
    assert 'my_pkg' in listed and 'tests' not in listed and 'docs' not in listed
    assert run_cli('pkg', 'executables', 'my_pkg').stdout == 'my_pkg my_node\n'
    assert run_cli('pkg', 'prefix', 'my_pkg', '--share').stdout == f'{project / "my_pkg"}\n'
    packages_line = next(line for line in run_cli('run', '--help').stdout.splitlines() if line.startswith('packages: '))
    assert 'my_pkg' in packages_line.split(': ', 1)[1].split(', ') and 'tests' not in packages_line
    assert_clean_failure(run_cli('run', 'tests', 'test_my_node'), "Package 'tests' not found")
    with pytest.raises(PackageNotFoundError):
        get_package_share_directory('tests')


def test_the_index_finds_shipped_and_message_packages():
    assert get_package_share_directory('demo_nodes') == str(REPO / 'nodes' / 'demo_nodes')
    assert get_package_share_directory('std_msgs') == str(REPO / 'interfaces' / 'std_msgs')
    assert get_package_share_directory('configs') == str(REPO / 'configs')
    assert get_package_prefix('demo_nodes') == str(REPO / 'nodes')
    assert get_packages_with_prefixes()['zros'] == str(REPO.parent)
    with pytest.raises(PackageNotFoundError, match="package 'no_such' not found"):
        get_package_share_directory('no_such')
    with pytest.raises(KeyError):   # as ament_index_python's
        get_package_share_directory('no_such')


def test_executables_read_the_index_once_per_node_start(tmp_path: Path, monkeypatch: pytest.MonkeyPatch):
    """`zros run` lists, names and loads an executable from one read of the package index (it
    read the directories six times per node start before zros.ament_index_python.executables)."""
    from zros.ament_index_python import executables as module
    (tmp_path / 'my_robot').mkdir()
    (tmp_path / 'my_robot' / 'spawn.py').write_text('def main():\n    return 7\n')
    (tmp_path / 'my_robot' / 'no_main.py').write_text('x = 1\n')
    monkeypatch.setenv('ZROS_NODE_PATH', str(tmp_path))
    reads = []
    monkeypatch.setattr(module, 'package_index', lambda: reads.append(1) or packages.package_index())
    index = module.Executables()
    assert index.load('demo_nodes', 'talker').__module__ == 'nodes.demo_nodes.talker'
    assert index.name('my_robot', 'spawn.py') == 'spawn' and index.name('my_robot', 'drive') is None
    assert index.load('my_robot', 'spawn.py')() == 7
    assert 'my_robot' in index.packages() and index.of('my_robot') == ['no_main', 'spawn']
    assert len(reads) == 1
    with pytest.raises(module.ExecutableNotFoundError, match="has no main"):
        index.load('my_robot', 'no_main')
    with pytest.raises(module.ExecutableNotFoundError, match="No executable 'spwn' found in package 'my_robot'. Did you mean 'spawn'"):
        index.load('my_robot', 'spwn')
    with pytest.raises(PackageNotFoundError, match="Package 'my_robo' not found"):
        index.load('my_robo', 'spawn')
    assert module.executables('nope') == []


def test_the_node_path_overlays_shipped_packages(tmp_path: Path, monkeypatch: pytest.MonkeyPatch):
    (tmp_path / 'demo_nodes' / 'launch').mkdir(parents=True)
    monkeypatch.setenv('ZROS_NODE_PATH', str(tmp_path))
    assert get_package_share_directory('demo_nodes') == str(tmp_path / 'demo_nodes')


def test_nodes_folder_is_grafted_into_the_package_data():
    """A shipped package's data of any type (maps, meshes, rviz files...) must install with zros."""
    manifest = (REPO / 'MANIFEST.in').read_text().split('\n')
    assert 'graft nodes' in manifest and 'graft configs' in manifest


@pytest.mark.parametrize('verb', [['pkg'], ['pkg', 'create', '-h']])
def test_pkg_help(verb: list[str]):
    result = run_cli(*verb)
    assert result.returncode == 0 and 'Traceback' not in result.stdout + result.stderr, result
