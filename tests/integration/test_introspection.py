"""The introspection verbs end to end: hz, bw, delay, echo's options, pub's options, node info,
graph, completion, --json, and clean one-line failures. Real CLI processes against real node
processes in one module-wide domain (a demo talker and a 50 Hz publisher script)."""
from __future__ import annotations

import json
import re
import shutil
import subprocess
import sys

import pytest
import yaml

from conftest import REPO, assert_clean_failure, wait_until

CLI = [sys.executable, '-m', 'zros.cli.main']

# Publishes, on an absolute schedule (so the average rate is exact however loaded the machine):
# /rate50 std_msgs/String 'n<i>' at 50 Hz, /stamped50 geometry_msgs/PoseStamped stamped now,
# and /joints sensor_msgs/JointState with arrays and strings.
RATE_SCRIPT = '''
import time, zros
from zros.node import Node
from interfaces.std_msgs.msg import String
from interfaces.geometry_msgs.msg import PoseStamped
from interfaces.sensor_msgs.msg import JointState
with zros.init():
    node = Node('rate50')
    strings = node.create_publisher(String, '/rate50', 10)
    stamped = node.create_publisher(PoseStamped, '/stamped50', 10)
    joints = node.create_publisher(JointState, '/joints', 10)
    print('ready', flush=True)
    start = time.monotonic()
    i = 0
    while True:
        i += 1
        strings.publish(String(data=f'n{i}'))
        msg = PoseStamped()
        msg.header.stamp = node.get_clock().now().to_msg()
        msg.header.frame_id = 'map'
        msg.pose.position.x = float(i % 2)
        stamped.publish(msg)
        joints.publish(JointState(name=['elbow', 'wrist'], position=[0.5, 1.5]))
        delay = start + i / 50.0 - time.monotonic()
        if delay > 0:
            time.sleep(delay)
'''


@pytest.fixture(autouse=True)
def _isolated(module_domain):
    """Every CLI call of this module runs in the module's test domain."""


@pytest.fixture(scope='module')
def talker(module_spawn):
    child = module_spawn.node('demo_nodes', 'talker')
    child.wait_for_output("Publishing: 'Hello World: 1'", timeout=15)
    return child


@pytest.fixture(scope='module')
def rate50(module_spawn):
    child = module_spawn.script(RATE_SCRIPT, name='rate50')
    child.wait_for_output('ready', timeout=15)
    return child


def run_until(spawner, args, text_or_predicate, timeout=15.0) -> str:
    """Run a long-running CLI verb as a child until its output satisfies the predicate, then stop it."""
    child = spawner(*CLI, *args, name=args[0] + '-' + args[1])
    try:
        if callable(text_or_predicate):
            wait_until(lambda: text_or_predicate(child.output()), timeout,
                       message=lambda: f'{args}; output so far:\n{child.output()}')
        else:
            child.wait_for_output(text_or_predicate, timeout=timeout)
        return child.output()
    finally:
        child.kill()


# -- hz / bw / delay --------------------------------------------------------------------------------
def test_hz_measures_50_hz_within_5_percent(rate50, module_spawn):
    def enough(output: str) -> bool:
        return len(re.findall(r'average rate: ', output)) >= 3
    output = run_until(module_spawn, ['topic', 'hz', '/rate50'], enough, timeout=20)
    reports = re.findall(r'average rate: ([\d.]+)\n\tmin: [\d.]+s max: [\d.]+s std dev: [\d.]+s window: (\d+)',
                         output)
    assert len(reports) >= 3, output
    rate, window = float(reports[-1][0]), int(reports[-1][1])
    assert abs(rate - 50.0) / 50.0 < 0.05, output
    assert window >= 100, output


def test_hz_window_and_filter(rate50, module_spawn):
    output = run_until(module_spawn, ['topic', 'hz', '/stamped50', '--window', '20',
                                      '--filter', 'm.pose.position.x == 1.0'],
                       lambda out: out.count('average rate') >= 2, timeout=20)
    rate, window = re.findall(r'average rate: ([\d.]+)\n.*window: (\d+)', output)[-1]
    assert int(window) == 20, output
    assert abs(float(rate) - 25.0) / 25.0 < 0.1, output  # every other message matches


def test_bw_reports_size_and_rate(rate50, module_spawn):
    output = run_until(module_spawn, ['topic', 'bw', '/rate50'], lambda out: out.count(' messages\n') >= 2)
    assert output.startswith('Subscribed to [/rate50]\n'), output
    match = re.search(r'([\d.]+) (B|KB|MB)/s from (\d+) messages\n\tMessage size mean: ([\d.]+) \2 '
                      r'min: ([\d.]+) \2 max: ([\d.]+) \2', output)
    assert match, output
    assert int(match.group(3)) >= 2


def test_delay_from_header_stamp(rate50, module_spawn):
    output = run_until(module_spawn, ['topic', 'delay', '/stamped50'], lambda out: out.count('average delay') >= 2)
    delay = float(re.findall(r'average delay: (-?[\d.]+)\n\tmin: -?[\d.]+s max: -?[\d.]+s std dev: [\d.]+s '
                             r'window: \d+', output)[-1])
    assert -0.05 < delay < 0.5, output


# -- echo ----------------------------------------------------------------------------------------------
def test_echo_csv_json_field_filter(rate50, zros_cli):
    csv = zros_cli('topic', 'echo', '/rate50', '--csv', '--once')
    assert csv.returncode == 0, csv
    assert re.fullmatch(r'n\d+\n', csv.stdout), csv
    js = zros_cli('topic', 'echo', '/stamped50', '--json', '--once')
    doc = json.loads(js.stdout)
    assert doc['header']['frame_id'] == 'map' and set(doc['pose']) == {'position', 'orientation'}, js
    field = zros_cli('topic', 'echo', '/stamped50', '--field', 'header.frame_id', '--once')
    assert field.stdout == 'map\n---\n', field
    # as in ros2, the filter sees the --field value
    filtered = zros_cli('topic', 'echo', '/stamped50', '--filter', 'm.x == 1.0',
                        '--field', 'pose.position', '--json', '--once')
    assert json.loads(filtered.stdout) == {'x': 1.0, 'y': 0.0, 'z': 0.0}, filtered
    numbers = zros_cli('topic', 'echo', '/rate50', '--filter', "int(m.data[1:]) % 5 == 0", '--csv', '--once')
    assert int(numbers.stdout.strip()[1:]) % 5 == 0, numbers


def test_echo_no_arr_no_str_flow(rate50, zros_cli):
    no_arr = zros_cli('topic', 'echo', '/joints', '--no-arr', '--once')
    doc = yaml.safe_load(no_arr.stdout.split('---')[0])
    # rosidl's IDL type names, as ros2 topic echo --no-arr prints them
    assert doc['position'] == '<sequence type: double, length: 2>', no_arr
    assert doc['name'] == '<sequence type: string, length: 2>', no_arr
    no_str = zros_cli('topic', 'echo', '/stamped50', '--no-str', '--once')
    assert yaml.safe_load(no_str.stdout.split('---')[0])['header']['frame_id'] == '<string length: <3>>', no_str
    full = zros_cli('topic', 'echo', '/joints', '--once')
    assert yaml.safe_load(full.stdout.split('---')[0])['position'] == [0.5, 1.5], full
    flow = zros_cli('topic', 'echo', '/joints', '--once', '--flow-style', '--field', 'name')
    assert flow.stdout.startswith('[elbow, wrist]'), flow


def test_echo_include_message_info(rate50, zros_cli):
    result = zros_cli('topic', 'echo', '/rate50', '-i', '--once')
    assert result.returncode == 0, result
    info_text, message_text = result.stdout.split('---\n')[:2]
    info = yaml.safe_load(info_text)
    assert set(info) == {'source_timestamp', 'received_timestamp', 'publication_sequence_number',
                         'reception_sequence_number'}, result
    assert 0 <= info['received_timestamp'] - info['source_timestamp'] < 5e9
    assert re.fullmatch(r'data: n\d+\n', message_text), result
    csv = zros_cli('topic', 'echo', '/rate50', '-i', '--csv', '--once')
    fields = csv.stdout.strip().split(',')
    assert len(fields) == 5 and fields[4].startswith('n') and int(fields[2]) >= 1, csv


def test_echo_raw_prints_payload_bytes(rate50, zros_cli):
    import msgpack
    result = zros_cli('topic', 'echo', '/rate50', '--raw', '--once')
    assert result.returncode == 0, result
    payload = eval(result.stdout.split('\n---')[0])  # noqa: S307 - the repr of a bytes object
    assert msgpack.unpackb(payload)[0].startswith('n')  # the header of a std_msgs/String: [data]


def test_echo_adapts_to_a_transient_local_publisher(module_spawn, zros_cli):
    """A late echo gets a latched message because it follows the publisher's durability."""
    pub = module_spawn(*CLI, 'topic', 'pub', '/latched', 'std_msgs/msg/String', '{data: kept}', '--once',
                       '-w', '0', '--qos-durability', 'transient_local', '--keep-alive', '30', name='latched')
    try:
        pub.wait_for_output('publishing #1', timeout=15)
        result = zros_cli('topic', 'echo', '/latched', '--once', '--timeout', '5')
        assert result.stdout == 'data: kept\n---\n', result
        info = zros_cli('topic', 'info', '/latched', '-v')
        assert 'Durability: TRANSIENT_LOCAL' in info.stdout, info
    finally:
        pub.kill()


# -- pub -------------------------------------------------------------------------------------------
def test_pub_stdin_streams_documents_to_echo(module_spawn):
    echo = module_spawn(*CLI, 'topic', 'echo', '/from_stdin', 'std_msgs/msg/String', '--csv', name='echo-stdin')
    try:
        text = '{data: one}\n{"data": "two"}\n---\ndata: three\n---\ndata: four\n'
        result = subprocess.run([*CLI, 'topic', 'pub', '/from_stdin', 'std_msgs/msg/String', '--stdin'],
                                input=text, capture_output=True, text=True, timeout=20, cwd=REPO)
        assert result.returncode == 0, result
        assert 'publishing #4' in result.stdout and 'publishing #5' not in result.stdout, result
        echo.wait_for_output('one\ntwo\nthree\nfour\n', timeout=10)
    finally:
        echo.kill()


def test_pub_stdin_bad_yaml_is_one_line(rate50):
    result = subprocess.run([*CLI, 'topic', 'pub', '/bad_stdin', 'std_msgs/msg/String', '--stdin', '-w', '0'],
                            input='data: [unclosed\n', capture_output=True, text=True, timeout=20, cwd=REPO)
    assert_clean_failure(result, 'YAML')


def test_pub_wait_for_subscriptions_and_qos_flags(module_spawn, zros_cli):
    result = zros_cli('topic', 'pub', '/nobody_listens', 'std_msgs/msg/String', '{data: x}', '--once', '-w', '1',
                      '--max-wait-time-secs', '0.5')
    assert result.returncode == 0, result
    assert 'timed out' in result.stderr and 'publishing #1' in result.stdout, result
    pub = module_spawn(*CLI, 'topic', 'pub', '/qos_flags', 'std_msgs/msg/String', '{data: q}', '--rate', '5',
                       '--qos-reliability', 'best_effort', '--qos-depth', '7', name='qos-pub')
    try:
        pub.wait_for_output('publishing #1', timeout=15)
        info = zros_cli('topic', 'info', '/qos_flags', '-v')
        assert 'Reliability: BEST_EFFORT' in info.stdout and 'History (Depth): KEEP_LAST (7)' in info.stdout, info
        # ros2 echo's adaptation: a best-effort publisher gets a best-effort echo (no QoS warning)
        echo = zros_cli('topic', 'echo', '/qos_flags', '--once', '--timeout', '5')
        assert echo.stdout == 'data: q\n---\n', echo
    finally:
        pub.kill()


# -- node info, list/info --json ------------------------------------------------------------------------
def test_node_info_sections_in_ros2_order(talker, zros_cli):
    result = zros_cli('node', 'info', '/talker')
    lines = result.stdout.splitlines()
    titles = [line.strip() for line in lines if line.startswith('  ') and not line.startswith('    ')]
    assert titles == ['Subscribers:', 'Publishers:', 'Service Servers:', 'Service Clients:', 'Action Servers:',
                      'Action Clients:'], result
    # an empty section is followed by an empty line, as ros2 prints it
    assert lines[lines.index('  Subscribers:') + 1] == '', result
    assert '    /talker/set_parameters: rcl_interfaces/srv/SetParameters' in lines, result


def test_json_on_list_and_info_verbs(talker, zros_cli):
    topics = json.loads(zros_cli('topic', 'list', '--json').stdout)
    chatter = next(t for t in topics if t['name'] == '/chatter')
    assert chatter['types'] == ['std_msgs/msg/String'] and chatter['publisher_count'] == 1
    info = json.loads(zros_cli('topic', 'info', '/chatter', '--json').stdout)
    assert info['publishers'][0]['node'] == '/talker'
    assert '/talker' in json.loads(zros_cli('node', 'list', '--json').stdout)
    node = json.loads(zros_cli('node', 'info', '/talker', '--json').stdout)
    assert node['Publishers']['/chatter'] == ['std_msgs/msg/String']
    interfaces = json.loads(zros_cli('interface', 'list', '-m', '--json').stdout)
    assert 'std_msgs/msg/String' in interfaces['messages']
    assert json.loads(zros_cli('interface', 'package', 'std_srvs', '--json').stdout)[0] == 'std_srvs/srv/Empty'


def test_topic_info_verbose_lists_qos(talker, zros_cli):
    result = zros_cli('topic', 'info', '/chatter', '-v')
    for line in ('Node name: talker', 'Node namespace: /', 'Topic type: std_msgs/msg/String', 'Endpoint type: PUBLISHER',
                 '  Reliability: RELIABLE', '  Durability: VOLATILE', '  Liveliness: AUTOMATIC'):
        assert line in result.stdout.splitlines(), result


# -- graph and completion --------------------------------------------------------------------------------
def test_graph_dot(talker, rate50, zros_cli, tmp_path):
    listener_free = zros_cli('graph')
    assert listener_free.returncode == 0, listener_free
    assert listener_free.stdout.startswith('digraph zros_graph {'), listener_free
    assert '"n:/talker" -> "t:/chatter";' in listener_free.stdout
    assert '/rosout' not in listener_free.stdout and '_zros_cli' not in listener_free.stdout
    target = tmp_path / 'g.dot'
    assert zros_cli('graph', '--dot', str(target), '--include-debug').returncode == 0
    text = target.read_text()
    assert '"n:/rate50" -> "t:/stamped50";' in text and '"t:/rosout"' in text
    content = json.loads(zros_cli('graph', '--json').stdout)
    assert ['n:/talker', 't:/chatter'] in content['edges']


def test_graph_svg_needs_graphviz(talker, zros_cli, tmp_path):
    result = zros_cli('graph', '--svg', str(tmp_path / 'g.svg'))
    if shutil.which('dot'):
        assert result.returncode == 0 and (tmp_path / 'g.svg').read_text().lstrip().startswith('<')
    else:
        assert_clean_failure(result, "'dot'", 'not installed')


def test_completion_bash_and_zsh(tmp_path):
    from zros.cli.main import VERBS
    result = subprocess.run([*CLI, 'completion', 'bash'], capture_output=True, text=True, timeout=20, cwd=REPO)
    assert result.returncode == 0, result
    script = result.stdout
    for verb in VERBS:
        assert verb in script
    assert 'complete -o default -F _zros_complete zros' in script
    assert '"topic echo") words="' in script and '--no-arr' in script
    assert 'zros topic list' in script and 'zros node list' in script
    path = tmp_path / 'zros.bash'
    path.write_text(script)
    syntax = subprocess.run(['bash', '-n', str(path)], capture_output=True, text=True)
    assert syntax.returncode == 0, syntax.stderr
    # complete 'zros topic ec' and 'zros topic echo --no-a' in a real bash
    probe = subprocess.run(['bash', '-c', f'source {path}; COMP_WORDS=(zros topic ec); COMP_CWORD=2; _zros_complete; '
                            'echo "${COMPREPLY[@]}"; COMP_WORDS=(zros topic echo /x --no-a); COMP_CWORD=4; '
                            '_zros_complete; echo "${COMPREPLY[@]}"'], capture_output=True, text=True, timeout=20)
    assert probe.stdout.splitlines() == ['echo', '--no-arr'], probe
    zsh = subprocess.run([*CLI, 'completion', 'zsh'], capture_output=True, text=True, timeout=20, cwd=REPO)
    assert 'bashcompinit' in zsh.stdout and '_zros_complete' in zsh.stdout


def test_verb_modules_import_lightly():
    """Building the whole parser (what every command does first) must not import heavy modules."""
    code = ('import sys; from zros.cli.main import build_parser; build_parser(); '
            "print(sorted(m for m in ('numpy', 'mcap', 'yaml', 'zenoh', 'interfaces') if m in sys.modules))")
    result = subprocess.run([sys.executable, '-c', code], capture_output=True, text=True, timeout=20, cwd=REPO)
    assert result.stdout.strip() == '[]', result


def test_a_command_imports_only_its_own_verb():
    """`zros node list` builds the parser of its verb alone: starting a command is most of its cost."""
    code = ('import sys; from zros.cli.main import VERBS, build_parser; build_parser("node"); '
            "print(sorted({m for m, _ in VERBS.values()} & set(sys.modules)))")
    result = subprocess.run([sys.executable, '-c', code], capture_output=True, text=True, timeout=20, cwd=REPO)
    assert result.stdout.strip() == "['zros.cli.node']", result


# -- errors: one line, non-zero, no traceback -----------------------------------------------------------------
ERROR_CASES = [
    (('topic', 'hz', '/nobody_here', '--timeout', '0.5'), ('/nobody_here',)),
    (('topic', 'bw', '/nobody_here', '--timeout', '0.5'), ('/nobody_here',)),
    (('topic', 'delay', '/nobody_here', '--timeout', '0.5'), ('/nobody_here',)),
    (('topic', 'delay', '/rate50', '--timeout', '5'), ('header', 'std_msgs/msg/String')),
    (('topic', 'echo', '/rate50', 'std_msgs/msg/Int32', '--once'), ('/rate50', 'std_msgs/msg/String',
                                                                    'std_msgs/msg/Int32')),
    (('topic', 'pub', '/rate50', 'std_msgs/msg/Int32', '{data: 1}', '--once'), ('std_msgs/msg/String',)),
    (('topic', 'echo', '/rate50', '--filter', 'm.data ==', '--once'), ('--filter',)),
    (('topic', 'echo', '/rate50', '--filter', 'm.nope', '--once'), ('nope',)),
    (('topic', 'echo', '/rate50', '--once', '--qos-profile', 'sensor_data', '--field', 'x'), ("'x'",)),
    (('topic', 'echo', '/nobody_here', 'std_msgs/msg/String', '--timeout', '0.3'), ('timed out',)),
    (('topic', 'echo', '/x', 'no_pkg/msg/Nope'), ('no_pkg/msg/Nope',)),
    (('topic', 'pub', '/x', 'std_msgs/msg/String', 'data: [', '--once'), ('YAML',)),
    (('node', 'info', '/nobody'), ('/nobody',)),
    (('interface', 'show', 'std_msgs/msg/Nope'), ('std_msgs/msg/Nope',)),
    (('graph', '--dot', '/nonexistent_dir/g.dot'), ('/nonexistent_dir/g.dot',)),
]


@pytest.mark.parametrize('args, fragments', ERROR_CASES, ids=[' '.join(a) for a, _ in ERROR_CASES])
def test_errors_are_one_clean_line(rate50, zros_cli, args, fragments):
    assert_clean_failure(zros_cli(*args, timeout=20), *fragments)


@pytest.mark.parametrize('args', [('topic', 'hz', '-h'), ('topic', 'bw', '-h'), ('topic', 'delay', '-h'),
                                  ('bag', 'record', '-h'), ('bag', 'play', '-h'), ('bag', 'info', '-h'),
                                  ('doctor', '-h'), ('doctor', 'hello', '-h'), ('graph', '-h'),
                                  ('completion', '-h')], ids=' '.join)
def test_new_verbs_have_help(capsys, args):
    from zros.cli.main import main
    with pytest.raises(SystemExit) as exited:
        main(list(args))
    assert exited.value.code == 0
    out, err = capsys.readouterr()
    assert out.lower().startswith('usage: zros ' + args[0]) and err == ''

