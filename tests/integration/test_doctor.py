"""`zros doctor` finds planted problems (type mismatch, duplicate names, incompatible QoS,
simulated time without /clock) and passes a healthy system; `zros doctor hello` between two
processes on loopback."""
from __future__ import annotations

import json
import re
import sys

import pytest

CLI = [sys.executable, '-m', 'zros.cli.main']

# Two processes, both named 'dup': one publishes String on /mixed and best-effort String on
# /lossy; the other publishes Int32 on /mixed, subscribes reliably to /lossy and uses sim time.
PLANTED = '''
import sys, time, zros
from zros.node import Node
from zros.qos import QoSProfile, ReliabilityPolicy
from zros.parameter import Parameter
from interfaces.std_msgs.msg import Int32, String
with zros.init():
    node = Node('dup')
    if sys.argv[1] == 'a':
        node.create_publisher(String, '/mixed', 10)
        node.create_publisher(String, '/lossy', QoSProfile(depth=5, reliability=ReliabilityPolicy.BEST_EFFORT))
    else:
        node.create_publisher(Int32, '/mixed', 10)
        node.create_subscription(String, '/lossy', lambda m: None, QoSProfile(depth=5))
        node.set_parameters([Parameter('use_sim_time', value=True)])
    print('ready', flush=True)
    while True:
        time.sleep(1)
'''


@pytest.fixture(autouse=True)
def _isolated(module_domain):
    """Every CLI call of this module runs in the module's test domain."""


@pytest.fixture(scope='module')
def planted(module_spawn):
    children = [module_spawn.script(PLANTED, side, name=f'planted-{side}') for side in ('a', 'b')]
    for child in children:
        child.wait_for_output('ready', timeout=15)
    return children


@pytest.fixture(scope='module')
def doctor_run(planted):
    from conftest import run_cli
    return run_cli('doctor', timeout=30)


def test_doctor_fails_on_planted_problems(doctor_run):
    assert doctor_run.returncode == 1, doctor_run
    assert 'Traceback' not in doctor_run.stdout + doctor_run.stderr
    lines = doctor_run.stdout.splitlines()
    assert lines[-1] == 'Failed modules: nodes topics qos', doctor_run
    assert lines[-2] == '3/6 check(s) failed', doctor_run


def test_doctor_finds_type_mismatch(doctor_run):
    assert re.search(r"^ERROR: \[topics\] topic '/mixed' has more than one type: std_msgs/msg/Int32 \(/dup\); "
                     r'std_msgs/msg/String \(/dup\)$', doctor_run.stdout, re.M), doctor_run


def test_doctor_finds_duplicate_node_names(doctor_run):
    assert "ERROR: [nodes] 2 nodes share the name '/dup'" in doctor_run.stdout, doctor_run


def test_doctor_finds_incompatible_qos(doctor_run):
    assert ("ERROR: [qos] topic '/lossy': incompatible QoS between publisher /dup and subscription /dup: "
            'Best effort publisher and reliable subscription') in doctor_run.stdout, doctor_run


def test_doctor_warns_about_sim_time_without_clock(doctor_run):
    assert re.search(r'^WARNING: \[clock\] .*use_sim_time.*nothing publishes /clock: /dup', doctor_run.stdout,
                     re.M), doctor_run


def test_doctor_report_and_json(planted, zros_cli):
    report = zros_cli('doctor', '--report', timeout=30)
    for section in ('   PLATFORM INFORMATION', '   VERSIONS', '   ZROS CONFIGURATION', '   CLOCK', '   NETWORK',
                    '   NODES', '   TOPIC LIST'):
        assert section in report.stdout.splitlines(), report
    assert re.search(r'^zenoh +: \d+\.\d+', report.stdout, re.M), report
    assert re.search(r'^hub running +: yes$', report.stdout, re.M), report
    assert re.search(r'^topic +: /mixed$', report.stdout, re.M), report
    data = json.loads(zros_cli('doctor', '--json', timeout=30).stdout)
    assert data['failed_modules'] == ['nodes', 'topics', 'qos']
    assert {f['module'] for f in data['findings'] if f['level'] == 'ERROR'} == {'nodes', 'topics', 'qos'}
    assert data['report']['VERSIONS']['zros']


def test_doctor_passes_a_healthy_system(domain, spawn, zros_cli):
    talker = spawn.node('demo_nodes', 'talker')
    listener = spawn.node('demo_nodes', 'listener')
    listener.wait_for_output('I heard', timeout=15)
    result = zros_cli('doctor', timeout=30)
    assert result.returncode == 0, result
    assert result.stdout.splitlines()[-1] == 'All 6 checks passed', result
    assert 'ERROR' not in result.stdout
    talker.kill()


def test_doctor_without_a_running_system(domain, zros_cli):
    result = zros_cli('doctor', '--report', timeout=30)
    assert result.returncode == 0, result
    assert 'no zros process is running in this domain' in result.stdout, result


def test_doctor_reports_an_unreachable_router(domain, zros_cli):
    import os
    env = dict(os.environ, ZROS_CONNECT='tcp/127.0.0.1:9')  # the discard port: nothing listens
    from conftest import run_cli
    result = run_cli('doctor', timeout=30, env=env)
    assert result.returncode == 1, result
    assert 'ERROR: [network] cannot reach tcp/127.0.0.1:9' in result.stdout, result


def test_doctor_hello_between_two_processes(domain, spawn):
    first = spawn(*CLI, 'doctor', 'hello', '-pp', '0.5', name='hello-1')
    second = spawn(*CLI, 'doctor', 'hello', '-pp', '0.5', '-t', '/canyouhearme', name='hello-2')
    import socket
    host = socket.gethostname()
    # each hears the other (by host:pid), and never counts itself
    second.wait_for_output(f'{host}:{first.pid}', timeout=20)
    first.wait_for_output(f'{host}:{second.pid}', timeout=20)
    output = first.output()
    assert 'MULTIMACHINE COMMUNICATION SUMMARY' in output
    assert 'Topic: /canyouhearme, Published Msg Count: ' in output
    assert f'{host}:{first.pid}' not in output
    row = re.search(rf'^ +{re.escape(host)}:{second.pid} +(\d+)', output, re.M)
    assert row and int(row.group(1)) >= 1, output


def test_doctor_hello_once(domain, zros_cli):
    result = zros_cli('doctor', 'hello', '-1', '-pp', '0.3', timeout=30)
    assert result.returncode == 0, result
    assert result.stdout.startswith('MULTIMACHINE COMMUNICATION SUMMARY\nTopic: /canyouhearme, '), result
