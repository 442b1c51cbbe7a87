"""Launch files from the wild: what ROS 2's launch_yaml and launch_ros accept (their own test
files are the reference), and bad input that must fail in one line."""
from __future__ import annotations

import sys
import textwrap
from pathlib import Path

import pytest

from conftest import assert_clean_failure, run_cli
from unit.test_launch_parse import error_of, only_process, plan_of, processes, ros_part, write  # noqa: F401 - fixtures
from integration.test_launch_python import REPORT_NODE, probe, reports  # noqa: F401 - fixture
from zros.launch.plan import LogMessage
from zros.parameter import ParameterFileError, load_parameter_file


def params_of(spec) -> dict:
    return spec.params[0].document['/**']['ros__parameters']


def test_parameter_values_follow_launch_ros(plan_of):
    """launch_ros's own frontend test (test_node_frontend.py), with its expected values."""
    spec = only_process(plan_of(r'''
        launch:
        - let: {name: a_string, value: "'[2, 5, 8]'"}
        - let: {name: a_list, value: '[2, 5, 8]'}
        - let: {name: my_value, value: '100'}
        - node:
            pkg: demo_nodes
            exec: talker
            param:
            - name: param_group1
              param:
              - {name: param3, value: [2, 5, 8]}
              - {name: param4, value: $(var a_list)}
              - {name: param5, value: $(var a_string)}
              - {name: param6, value: [2., 5., 8.]}
              - {name: param7, value: ['2', '5', '8']}
              - {name: param8, value: ["'2'", "'5'", "'8'"]}
              - {name: param9, value: ["\\'2\\'", "\\'5\\'", "\\'8\\'"]}
              - {name: param10, value: ["'asd'", "'bsd'", "'csd'"]}
              - {name: param11, value: ['\asd', '\bsd', '\csd']}
              - {name: param12, value: ''}
              - {name: param13, value: '$(var my_value)', type: str}
              - {name: param14, value: ["'2'", "'5'", "'8'"], type: list_of_str}
              - {name: param15, value: ['2', '5', '8'], type: list_of_str}
              - {name: param16, value: ['1', '2'], type: list_of_int}
              - {name: param17, value: '[1.5, 2]', type: list_of_float}
              - {name: param18, value: ['true', 'false'], type: list_of_bool}
        '''))
    group = params_of(spec)['param_group1']
    assert group == {
        'param3': [2, 5, 8], 'param4': [2, 5, 8], 'param5': '[2, 5, 8]', 'param6': [2.0, 5.0, 8.0],
        'param7': ['2', '5', '8'], 'param8': ["'2'", "'5'", "'8'"], 'param9': ["'2'", "'5'", "'8'"],
        'param10': ["'asd'", "'bsd'", "'csd'"], 'param11': ['asd', 'bsd', 'csd'], 'param12': '',
        'param13': '100', 'param14': ["'2'", "'5'", "'8'"], 'param15': ['2', '5', '8'], 'param16': [1, 2],
        'param17': [1.5, 2.0], 'param18': [True, False]}


@pytest.mark.parametrize('param, fragment', [
    ("{name: p, value: [1, 'a']}", 'Expected a non-empty sequence with items of one type'),
    ("{name: p, value: ['x'], type: list_of_int}", "expected an int, got string 'x'"),
    ("{name: p, value: 3, type: list_of_str}", 'expected a list for type list_of_str'),
    ("{name: p, value: 1, type: list_of_nothing}", 'expected one of str, int, float, bool, list_of_str'),
])
def test_bad_parameter_types_are_located(plan_of, param: str, fragment: str):
    message = error_of(plan_of, f'''
        launch:
        - node:
            pkg: demo_nodes
            exec: talker
            param:
            - {param}
        ''')
    assert 'test.launch.yaml:' in message and fragment in message, message


def test_node_without_package_runs_an_executable_from_path(plan_of):
    spec = only_process(plan_of(f'''
        launch:
        - node:
            exec: {sys.executable}
            args: -c 'import sys; print(sys.argv[1:])'
            name: my_listener
            namespace: my_ns
        '''))
    assert list(spec.cmd_head[:3]) == [sys.executable, '-c', 'import sys; print(sys.argv[1:])']
    assert ros_part(spec) == ['-r', '__node:=my_listener', '-r', '__ns:=/my_ns']
    assert spec.node.package == '' and 'from PATH' in plan_of(f'''
        launch:
        - node: {{exec: {sys.executable}}}
        ''').describe()
    message = error_of(plan_of, 'launch:\n- node: {exec: no-such-program-zz}\n')
    assert "node: exec: executable 'no-such-program-zz' not found on PATH" in message


def test_param_substitution_and_reset(plan_of):
    plan = plan_of('''
        launch:
        - set_parameter: {name: rate, value: 10}
        - set_parameter: {name: mode, value: fast}
        - log: {message: 'rate $(param rate) mode $(param mode) other $(param other 5)'}
        - let: {name: kept, value: kept-value}
        - let: {name: dropped, value: dropped-value}
        - reset:
            keep:
            - {name: kept, value: $(var kept)}
            - {name: added, value: new}
        - log: {message: '$(var kept) $(var added) $(var dropped gone) $(param rate none)'}
        ''')
    assert [e.message for e in plan.effects if isinstance(e, LogMessage)] == [
        'rate 10 mode fast other 5', 'kept-value new gone none']


def test_composable_nodes_in_yaml_run_as_processes(plan_of):
    """launch_ros's frontend test of node_container / load_composable_node, on zros's packages."""
    plan = plan_of('''
        launch:
        - node_container:
            pkg: rclcpp_components
            exec: component_container
            name: my_container
            namespace: ''
            args: 'test_args'
            composable_node:
            - pkg: demo_nodes
              plugin: demo_nodes::Talker
              name: talker
              namespace: test_namespace
              remap: [{from: chatter, to: /remap/chatter}]
              param: [{name: use_sim_time, value: true}]
              extra_arg: [{name: use_intra_process_comms, value: 'true'}]
        - load_composable_node:
            target: my_container
            composable_node:
            - pkg: demo_nodes
              plugin: demo_nodes::Listener
              name: listener
              namespace: test_namespace
              remap: [{from: chatter, to: /remap/chatter}]
        ''')
    notes = [e.message for e in plan.effects if isinstance(e, LogMessage)]
    assert notes == ["zros has no component containers: composable node 'talker' of container '/my_container' "
                     'runs as its own process',
                     "zros has no component containers: composable node 'listener' of container '/my_container' "
                     'runs as its own process']
    talker, listener = processes(plan)
    assert (talker.node.name, talker.node.namespace, talker.node.executable) == ('talker', '/test_namespace', 'talker')
    assert ros_part(talker)[-2:] == ['-r', 'chatter:=/remap/chatter']
    assert params_of(talker) == {'use_sim_time': True}
    assert listener.node.executable == 'listener'
    message = error_of(plan_of, '''
        launch:
        - node_container: {pkg: rclcpp_components, exec: component_container, name: c, namespace: ''}
        - load_composable_node:
            target: c
            composable_node: [{pkg: demo_nodes, plugin: demo_nodes::Nothing, name: x}]
        ''')
    assert "composable node plugin 'demo_nodes::Nothing': no executable Nothing or nothing" in message


def test_nested_namespace_parameter_files(tmp_path: Path):
    """launch_ros's example parameter files: namespaces nest, wildcards apply to every node."""
    nested = tmp_path / 'nested.yaml'
    nested.write_text(textwrap.dedent('''
        /my_ns:
            my_node:
                ros__parameters:
                    some_int: 42
                    some_list:
                        sub_list:
                            some_integers: [1, 2, 3, 4]
        '''))
    multiple = tmp_path / 'multiple.yaml'
    multiple.write_text(textwrap.dedent('''
        /ns_1:
          /node_1:
            ros__parameters: {param_1: 1, param_2: 2}
        /**:
          ros__parameters: {param_2: 22, param_3: 33}
        ns_2/node_2:
            ros__parameters: {param_3: 3}
        '''))
    assert load_parameter_file(str(nested), '/my_ns/my_node') == {
        'some_int': 42, 'some_list.sub_list.some_integers': [1, 2, 3, 4]}
    assert load_parameter_file(str(nested), '/my_node') == {}
    assert load_parameter_file(str(multiple), '/ns_1/node_1') == {'param_1': 1, 'param_2': 22, 'param_3': 33}
    assert load_parameter_file(str(multiple), '/ns_2/node_2') == {'param_2': 22, 'param_3': 3}
    bad = tmp_path / 'bad.yaml'
    bad.write_text('/ns:\n  node:\n    value: 1\n')
    with pytest.raises(ParameterFileError, match="node entry '/ns/node' has no 'ros__parameters' key"):
        load_parameter_file(str(bad), '/ns/node')


def test_a_yaml_launch_run_with_a_nested_namespace_file_and_a_node_without_package(probe: Path, write, tmp_path: Path):
    (probe / 'param' / 'nested.yaml').write_text('/robots:\n  report:\n    ros__parameters:\n      depth: 3\n')
    path = write('wild.launch.yaml', f'''
        launch:
        - set_parameter: {{name: level, value: 4}}
        - node:
            pkg: probe
            exec: report
            namespace: robots
            output: screen
            param:
            - from: $(find-pkg-share probe)/param/nested.yaml
            - {{name: copied, value: $(param level)}}
        - node:
            exec: {sys.executable}
            args: -c 'import sys; print("ARGS", sys.argv[1:])'
            name: bare
            output: screen
        ''')
    result = run_cli('launch', path, '--log-dir', tmp_path / 'log', timeout=60)
    assert result.returncode == 0, result
    report = reports(result.stdout)['/robots/report']
    assert report['params'] == {'depth': 3, 'level': 4, 'copied': 4, 'start_type_description_service': True,
                                'use_sim_time': False}
    assert "ARGS ['--ros-args', '-r', '__node:=bare', '--params-file', " in result.stdout, result  # set_parameter too


# -- bad input (issue: reliability) ------------------------------------------------------------
def test_a_mapping_where_a_list_is_required_is_refused(plan_of):
    message = error_of(plan_of, '''
        launch:
        - node:
            pkg: demo_nodes
            exec: talker
            param: {name: x, value: 1}
        ''')
    assert message.endswith("test.launch.yaml:5: node: param: expected a list of mappings, got a mapping: "
                            "write 'param:' followed by '- ...' items"), message


def test_a_launch_that_sets_a_string_parameter_to_a_number_stops_that_node(write, tmp_path: Path):
    """rclpy refuses an override of another type when the parameter is declared; so does zros."""
    path = write('typed.launch.yaml', '''
        launch:
        - node:
            pkg: demo_nodes
            exec: param_talker
            param: [{name: published_text, value: 42}]
        ''')
    result = run_cli('launch', path, '--log-dir', tmp_path / 'log', timeout=60)
    assert result.returncode == 0, result                      # a node that dies does not fail the launch
    assert "Trying to set parameter 'published_text' to '42' of type 'INTEGER', expecting type 'STRING'" \
        in result.stdout, result
    assert 'process has died' in result.stdout and 'Traceback' not in result.stdout, result


def test_binary_launch_file_on_the_cli_is_one_line(tmp_path: Path):
    blob = tmp_path / 'blob.launch.yaml'
    blob.write_bytes(bytes(range(256)))
    assert_clean_failure(run_cli('launch', blob), 'not a launch file: binary data, not UTF-8 text')
