"""ros2cli's output formats where users script against them, as snapshots: `service call`'s repr
form, `action send_goal`'s layout, `topic pub`'s wait, `topic hz` over several topics, `topic bw`'s
units, `topic info -v`'s type hash, `param dump --print`, `wtf`, each verb's `--json`, and the bad
input that used to pass (`param set NODE 'bad name!'`, `topic pub --rate -1`). Expected texts
follow ros2cli's own tests (ros2service/ros2action/ros2topic test_cli.py)."""
from __future__ import annotations

import json
import re

import pytest

from conftest import assert_clean_failure, wait_until
from integration.test_introspection import CLI, run_until

STRING_RIHS01 = 'RIHS01_df668c740482bbd48fb39d76a70dfd4bd59db1288021743503259e948f6b1a18'

# /fmt_fast at 20 Hz and /fmt_slow at 5 Hz (std_msgs/String), parameters, and /fmt_add.
SOURCE = '''
import time, zros
from zros.node import Node
from interfaces.std_msgs.msg import String
from interfaces.example_interfaces.srv import AddTwoInts
with zros.init():
    node = Node('fmt_source')
    node.declare_parameter('speed', 1.5)
    node.declare_parameter('wheels.count', 4)
    node.declare_parameter('name', 'robot')
    def add(request, response):
        response.sum = request.a + request.b
        return response
    node.create_service(AddTwoInts, '/fmt_add', add)
    fast = node.create_publisher(String, '/fmt_fast', 10)
    slow = node.create_publisher(String, '/fmt_slow', 10)
    node.create_timer(0.05, lambda: fast.publish(String(data='x' * 100)))
    node.create_timer(0.2, lambda: slow.publish(String(data='y')))
    print('ready', flush=True)
    zros.spin(node)
'''


@pytest.fixture(autouse=True)
def _isolated(module_domain):
    """Every CLI call of this module runs in the module's test domain."""


@pytest.fixture(scope='module')
def source(module_spawn):
    child = module_spawn.script(SOURCE, name='fmt_source')
    child.wait_for_output('ready', timeout=15)
    return child


def test_service_call_prints_repr_like_ros2(source, zros_cli):
    call = zros_cli('service', 'call', '/fmt_add', 'example_interfaces/srv/AddTwoInts', '{a: 2, b: 40}')
    assert call.returncode == 0, call
    lines = call.stdout.splitlines()
    start = lines.index('requester: making request: example_interfaces.srv.AddTwoInts_Request(a=2, b=40)')
    assert lines[start:] == ['requester: making request: example_interfaces.srv.AddTwoInts_Request(a=2, b=40)',
                             '', 'response:', 'example_interfaces.srv.AddTwoInts_Response(sum=42)', ''], call
    as_json = zros_cli('service', 'call', '/fmt_add', 'example_interfaces/srv/AddTwoInts', '{a: 1, b: 2}', '--json')
    assert as_json.returncode == 0 and json.loads(as_json.stdout) == {'sum': 3}, as_json


def test_options_before_the_positionals(source, zros_cli):
    """ros2cli's order-free options (tests/unit/test_cli_option_order.py checks every verb's parser)."""
    call = zros_cli('service', 'call', '--json', '/fmt_add', 'example_interfaces/srv/AddTwoInts', '{a: 2, b: 40}')
    assert call.returncode == 0 and json.loads(call.stdout) == {'sum': 42}, call
    echo = zros_cli('topic', 'echo', '--once', '--field', 'data', '/fmt_slow', 'std_msgs/msg/String')
    assert echo.returncode == 0 and echo.stdout == 'y\n---\n', echo
    got = zros_cli('param', 'get', '--hide-type', '/fmt_source', 'speed')
    assert got.returncode == 0 and got.stdout.strip() == '1.5', got


def test_action_send_goal_layout_and_json(spawn, domain, zros_cli):
    spawn.node('demo_nodes', 'fibonacci_action_server', '--ros-args', '-p', 'step_period:=0.02')
    sent = zros_cli('action', 'send_goal', '/fibonacci', 'action_tutorials_interfaces/action/Fibonacci',
                    '{order: 3}', timeout=30)
    assert sent.returncode == 0, sent
    lines = sent.stdout.splitlines()
    assert lines[:4] == ['Waiting for an action server to become available...', 'Sending goal:', '     order: 3', '']
    assert re.fullmatch('Goal accepted with ID: [0-9a-f]{32}', lines[4]) and lines[5] == '', sent
    assert lines[6:] == ['Result:', '    sequence:', '- 0', '- 1', '- 1', '- 2', '',
                         'Goal finished with status: SUCCEEDED'], sent
    as_json = zros_cli('action', 'send_goal', '/fibonacci', 'action_tutorials_interfaces/action/Fibonacci',
                       '{order: 2}', '-f', '--json', timeout=30)
    records = [json.loads(line) for line in as_json.stdout.splitlines()]
    accepted = [r for r in records if 'accepted' in r]   # feedback may come before the acceptance
    assert as_json.returncode == 0 and accepted[0]['accepted'] and len(accepted[0]['goal_id']) == 32, as_json
    assert records[-1] == {'status': 'SUCCEEDED', 'result': {'sequence': [0, 1, 1]}}
    feedback = [r['feedback'] for r in records if 'feedback' in r]
    assert feedback and len(records) == len(feedback) + 2, records


def test_topic_pub_says_what_it_waits_for(domain, zros_cli):
    result = zros_cli('topic', 'pub', '--once', '/fmt_nobody', 'std_msgs/msg/String', '{data: hi}',
                      '--max-wait-time-secs', '1.5')
    assert result.returncode == 0, result
    assert result.stdout.startswith('Waiting for at least 1 matching subscription(s)...\n'), result
    assert 'publisher: beginning loop' in result.stdout and 'publishing anyway' in result.stderr, result
    assert_clean_failure(zros_cli('topic', 'pub', '/x', 'std_msgs/msg/String', '--rate', '-1'),
                         '--rate must be > 0, got -1')
    assert_clean_failure(zros_cli('topic', 'pub', '/x', 'std_msgs/msg/String', '-r', '-0.5'), '--rate must be > 0')


def test_topic_hz_over_several_topics_prints_ros2s_table(source, module_spawn):
    def table_with_both(text):
        blocks = [b for b in text.split('\n\n') if b.lstrip().startswith('topic')]
        return blocks and all(t in blocks[-1] for t in ('/fmt_fast', '/fmt_slow'))
    out = run_until(module_spawn, ['topic', 'hz', '/fmt_fast', '/fmt_slow'], table_with_both, timeout=20)
    assert 'Subscribed to [/fmt_fast]' in out and 'Subscribed to [/fmt_slow]' in out
    block = [b for b in out.split('\n\n') if b.lstrip().startswith('topic')][-1].strip('\n').splitlines()
    assert re.fullmatch(r' *topic *   rate  +min_delta   max_delta   std_dev   window', block[0]), block
    assert block[1] == '=' * len(block[0]), block
    rows = {row.split()[0]: [float(v) for v in row.split()[1:]] for row in block[2:]}
    assert 14 < rows['/fmt_fast'][0] < 26 and 3 < rows['/fmt_slow'][0] < 7, rows


def test_topic_bw_prints_ros2s_units(source, module_spawn):
    out = run_until(module_spawn, ['topic', 'bw', '/fmt_fast'], 'Message size mean', timeout=20)
    lines = out.splitlines()
    i = next(n for n, line in enumerate(lines) if line.startswith('\tMessage size mean'))
    # ~20 messages/s of ~110 bytes: under 1000 B/s... or just over: either B with no decimals or KB
    assert re.fullmatch(r'(\d+ B|\d+\.\d\d KB)/s from \d+ messages', lines[i - 1]), lines
    unit = 'B' if lines[i - 1].split('/s')[0].endswith(' B') else 'KB'
    number = r'\d+' if unit == 'B' else r'\d+\.\d\d'
    assert re.fullmatch(rf'\tMessage size mean: {number} {unit} min: {number} {unit} max: {number} {unit}',
                        lines[i]), lines


def test_topic_info_verbose_prints_ros2s_type_hash(source, zros_cli):
    info = zros_cli('topic', 'info', '-v', '/fmt_fast')
    assert info.returncode == 0, info
    assert f'Topic type hash: {STRING_RIHS01}' in info.stdout.splitlines(), info
    as_json = json.loads(zros_cli('topic', 'info', '/fmt_fast', '--json').stdout)
    assert as_json['publishers'][0]['type_hash_rihs01'] == STRING_RIHS01


def test_param_dump_print_and_bad_names(source, zros_cli, tmp_path):
    printed = zros_cli('param', 'dump', '/fmt_source', '--print')
    assert printed.returncode == 0, printed
    assert printed.stdout.startswith('/fmt_source:\n  ros__parameters:\n'), printed
    assert '    speed: 1.5\n' in printed.stdout and '    wheels:\n      count: 4\n' in printed.stdout, printed
    both = zros_cli('param', 'dump', '/fmt_source', '--print', '--output-dir', str(tmp_path))
    assert (tmp_path / 'fmt_source.yaml').read_text() in both.stdout, both
    refused = assert_clean_failure(zros_cli('param', 'set', '/fmt_source', 'bad name!', '1'), "'bad name!'")
    assert 'invalid parameter name' in refused
    assert zros_cli('param', 'get', '/fmt_source', 'speed').stdout.strip() == 'Double value is: 1.5'


def test_wtf_is_doctor(domain, zros_cli):
    doctor = zros_cli('doctor', '--json')
    wtf = zros_cli('wtf', '--json')
    assert wtf.returncode == doctor.returncode, (wtf, doctor)
    assert json.loads(wtf.stdout).keys() == json.loads(doctor.stdout).keys()


def test_hz_and_bw_wait_for_each_topic(domain, spawn):
    child = spawn(*CLI, 'topic', 'hz', '/fmt_never', '/fmt_never_either', name='hz-none')
    wait_until(lambda: 'WARNING: topic [/fmt_never] does not appear to be published yet' in child.output(), 15,
               message=child.output)
    child.kill()
