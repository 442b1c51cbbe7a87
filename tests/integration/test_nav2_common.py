"""nav2_common.launch (RewrittenYaml, ReplaceString, HasNodeParams) as Nav2's launch files use
them: the rewriting rules without processes, then inside a launch file run with `--print`."""
from __future__ import annotations

from pathlib import Path

import yaml

from conftest import run_cli
from zros.nav2_common.launch.rewritten_yaml import rewrite

PARAMS = {
    'amcl': {'ros__parameters': {'use_sim_time': False, 'base_frame_id': 'base_footprint', 'alpha1': 0.2}},
    'map_server': {'ros__parameters': {'use_sim_time': False, 'yaml_filename': 'turtlebot3_world.yaml'}},
    'controller_server': {'ros__parameters': {'FollowPath': {'plugin': 'dwb'}, 'list': [{'a': 1}, {'a': 2}]}},
}


def fresh() -> dict:
    return yaml.safe_load(yaml.safe_dump(PARAMS))


def test_leaf_keys_are_replaced_everywhere_as_strings():
    out = rewrite(fresh(), {'use_sim_time': 'True', 'yaml_filename': '/maps/house.yaml'}, {}, '', False)
    assert out['amcl']['ros__parameters']['use_sim_time'] == 'True'
    assert out['map_server']['ros__parameters']['use_sim_time'] == 'True'
    assert out['map_server']['ros__parameters']['yaml_filename'] == '/maps/house.yaml'


def test_convert_types_reads_values_as_yaml_scalars():
    out = rewrite(fresh(), {'use_sim_time': 'true', 'amcl.ros__parameters.alpha1': '0.5'}, {}, '', True)
    assert out['amcl']['ros__parameters']['use_sim_time'] is True
    assert out['amcl']['ros__parameters']['alpha1'] == 0.5


def test_dotted_paths_replace_add_and_index_lists():
    out = rewrite(fresh(), {'amcl.ros__parameters.laser_model_type': 'beam',   # added: through ros__parameters
                            'controller_server.ros__parameters.list.1.a': '7',  # a list item
                            'bt_navigator.other.key': 'x'}, {}, '', False)      # neither there nor parameters
    assert out['amcl']['ros__parameters']['laser_model_type'] == 'beam'
    assert out['controller_server']['ros__parameters']['list'] == [{'a': 1}, {'a': '7'}]
    assert 'bt_navigator' not in out


def test_root_key_and_key_rewrites():
    out = rewrite(fresh(), {}, {'base_footprint': 'robot1/base_footprint', 'amcl': 'amcl_renamed'}, 'robot1', False)
    assert list(out) == ['robot1']
    assert 'amcl_renamed' in out['robot1'] and 'amcl' not in out['robot1']
    assert rewrite(fresh(), {}, {}, '', False) == PARAMS


LAUNCH = '''
from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument, LogInfo
from launch.substitutions import LaunchConfiguration
from nav2_common.launch import HasNodeParams, ReplaceString, RewrittenYaml


def generate_launch_description():
    params = LaunchConfiguration('params_file')
    rewritten = RewrittenYaml(source_file=params, root_key=LaunchConfiguration('namespace'),
                              param_rewrites={'use_sim_time': LaunchConfiguration('use_sim_time')},
                              convert_types=True)
    return LaunchDescription([
        DeclareLaunchArgument('params_file'), DeclareLaunchArgument('namespace', default_value=''),
        DeclareLaunchArgument('use_sim_time', default_value='false'),
        LogInfo(msg=['rewritten=', rewritten]),
        LogInfo(msg=['replaced=', ReplaceString(params, {'base_footprint': 'robot1/base_footprint'})]),
        LogInfo(msg=['has_amcl=', HasNodeParams(params, 'amcl'), ' has_route=', HasNodeParams(params, 'route_server')]),
    ])
'''


def test_in_a_launch_file_under_nav2s_names(tmp_path: Path):
    params = tmp_path / 'nav2_params.yaml'
    params.write_text(yaml.safe_dump(PARAMS))
    launch = tmp_path / 'bringup.launch.py'
    launch.write_text(LAUNCH)
    result = run_cli('launch', launch, f'params_file:={params}', 'namespace:=robot1', 'use_sim_time:=true',
                     '--print', '--log-dir', tmp_path / 'log', timeout=60)
    assert result.returncode == 0, result
    lines = {line.split('=', 1)[0].split()[-1]: line.split('=', 1)[1] for line in result.stdout.splitlines()
             if '=' in line and 'log [INFO]' in line}
    rewritten = yaml.safe_load(Path(lines['rewritten']).read_text())
    assert rewritten['robot1']['amcl']['ros__parameters']['use_sim_time'] is True
    assert Path(lines['rewritten']).parent == tmp_path / 'log'
    assert 'robot1/base_footprint' in Path(lines['replaced']).read_text()
    assert 'has_amcl=True has_route=False' in result.stdout, result.stdout


def test_a_missing_source_file_is_one_line(tmp_path: Path):
    launch = tmp_path / 'bringup.launch.py'
    launch.write_text(LAUNCH)
    result = run_cli('launch', launch, f'params_file:={tmp_path}/nope.yaml', '--print', '--log-dir', tmp_path / 'log',
                     timeout=60)
    assert result.returncode != 0 and 'Traceback' not in result.stderr
    assert "RewrittenYaml: cannot read" in result.stderr and 'nope.yaml' in result.stderr, result


def test_parse_multirobot_pose_reads_the_command_line(monkeypatch):
    from zros.nav2_common.launch import ParseMultiRobotPose
    monkeypatch.setattr('sys.argv', ['zros', 'launch', 'nav2_bringup', 'cloned_multi_tb3_simulation_launch.py',
                                     'robots:=robot1={x: 1.0, y: 1.0}; robot2={x: -1.0, y: 1.0, yaw: 1.57};'])
    robots = ParseMultiRobotPose('robots').value()
    assert list(robots) == ['robot1', 'robot2']
    assert robots['robot2'] == {'x': -1.0, 'y': 1.0, 'z': 0.0, 'roll': 0.0, 'pitch': 0.0, 'yaw': 1.57}
    monkeypatch.setattr('sys.argv', ['zros', 'launch', 'x.launch.py'])
    assert ParseMultiRobotPose('robots').value() == {}


def test_a_multi_robot_launch_reads_robots_from_the_command_line(tmp_path: Path):
    launch = tmp_path / 'multi.launch.py'
    launch.write_text('''
from launch import LaunchDescription
from launch.actions import LogInfo
from nav2_common.launch import ParseMultiRobotPose


def generate_launch_description():
    robots = ParseMultiRobotPose('robots').value()
    return LaunchDescription([LogInfo(msg=f"{name} at {pose['x']} {pose['y']}") for name, pose in robots.items()])
''')
    result = run_cli('launch', launch, 'robots:=tb1={x: 2.0, y: 0.5}; tb2={x: -2.0}', '--print', '--log-dir',
                     tmp_path / 'log', timeout=60)
    assert result.returncode == 0, result
    assert 'tb1 at 2.0 0.5' in result.stdout and 'tb2 at -2.0 0.0' in result.stdout, result.stdout
