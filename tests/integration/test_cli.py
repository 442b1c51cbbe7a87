"""The `zros` command line end to end: real CLI processes against a real talker process."""
from __future__ import annotations

import re
import sys
import threading
import time

import pytest
import yaml

from conftest import assert_clean_failure

from zros.executors import SingleThreadedExecutor
from zros.node import Node

from interfaces.std_msgs.msg import Int32, String


@pytest.fixture(autouse=True)
def _isolated(module_domain):
    """Every CLI call of this module runs in a test domain, never the developer's."""


@pytest.fixture(scope='module')
def talker(module_spawn):
    """One demo talker for the module (in the module's domain), publishing on /chatter."""
    child = module_spawn.node('demo_nodes', 'talker')
    child.wait_for_output("Publishing: 'Hello World: 1'", timeout=10)
    return child


# -- graph verbs against the talker -------------------------------------------------------
def test_topic_list_with_types(talker, zros_cli):
    result = zros_cli('topic', 'list', '-t')
    assert result.returncode == 0, result
    lines = result.stdout.splitlines()
    assert '/chatter [std_msgs/msg/String]' in lines
    assert '/rosout [rcl_interfaces/msg/Log]' in lines
    plain = zros_cli('topic', 'list')
    assert '/chatter' in plain.stdout.splitlines()
    assert zros_cli('topic', 'list', '-c').stdout.strip() == str(len(plain.stdout.splitlines()))


def test_node_list(talker, zros_cli):
    result = zros_cli('node', 'list')
    assert result.returncode == 0, result
    assert result.stdout.splitlines() == ['/talker']  # the CLI's own node is hidden
    assert zros_cli('node', 'list', '-c').stdout.strip() == '1'


def test_node_info(talker, zros_cli):
    result = zros_cli('node', 'info', '/talker')
    assert result.returncode == 0, result
    lines = result.stdout.splitlines()
    assert lines[0] == '/talker'
    publishers = lines.index('  Publishers:')
    assert '    /chatter: std_msgs/msg/String' in lines[publishers:]
    assert '  Subscribers:' in lines


def test_topic_echo_once(talker, zros_cli):
    result = zros_cli('topic', 'echo', '/chatter', '--once')
    assert result.returncode == 0, result
    assert re.fullmatch(r"data: 'Hello World: \d+'\n---\n", result.stdout), result


def test_topic_echo_field(talker, zros_cli):
    result = zros_cli('topic', 'echo', '/chatter', '--once', '--field', 'data')
    assert result.returncode == 0, result
    assert re.fullmatch(r"'Hello World: \d+'\n---\n", result.stdout), result


def test_topic_echo_with_explicit_type_and_json(talker, zros_cli):
    result = zros_cli('topic', 'echo', '/chatter', 'std_msgs/msg/String', '--once', '--json')
    assert result.returncode == 0, result
    import json
    assert re.fullmatch(r'Hello World: \d+', json.loads(result.stdout)['data']), result


def test_topic_info_counts(talker, zros_cli):
    result = zros_cli('topic', 'info', '/chatter')
    assert result.returncode == 0, result
    assert result.stdout.splitlines() == ['Type: std_msgs/msg/String', 'Publisher count: 1',
                                          'Subscription count: 0']
    verbose = zros_cli('topic', 'info', '/chatter', '-v')
    assert 'Node name: talker' in verbose.stdout
    assert 'Reliability: RELIABLE' in verbose.stdout
    assert 'History (Depth): KEEP_LAST (10)' in verbose.stdout


def test_topic_type_and_find(talker, zros_cli):
    result = zros_cli('topic', 'type', '/chatter')
    assert (result.returncode, result.stdout) == (0, 'std_msgs/msg/String\n'), result
    # a relative name is taken from the root namespace
    assert zros_cli('topic', 'type', 'chatter').stdout == 'std_msgs/msg/String\n'
    found = zros_cli('topic', 'find', 'std_msgs/msg/String')
    assert found.stdout.splitlines() == ['/chatter'], found


# -- echo and pub in a private domain ----------------------------------------------------------
def test_topic_pub_times_reaches_in_process_subscriber(domain, spawn, context, spin_for):
    node = Node('pub_target', context=context)
    received = []
    node.create_subscription(String, '/x', received.append, 10)
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(node)
    pub = spawn(sys.executable, '-m', 'zros.cli.main', 'topic', 'pub', '/x', 'std_msgs/msg/String',
                '{data: hi}', '--times', '3', '--rate', '5', name='pub')
    started = time.monotonic()
    spin_for(executor, lambda: len(received) >= 3, timeout=10, message=lambda: f'3 messages; pub:\n{pub.output()}')
    assert pub.wait(10) == 0, pub.output()
    assert [m.data for m in received] == ['hi', 'hi', 'hi']
    assert time.monotonic() - started >= 0.35  # three messages at 5 Hz span 0.4 s
    executor.spin_once(timeout_sec=0.3)
    assert len(received) == 3
    output = pub.output()
    assert 'publisher: beginning loop' in output
    assert "publishing #3: std_msgs.msg.String(data='hi')" in output
    assert 'publishing #4' not in output


def test_topic_pub_reaches_echo_process(domain, spawn, zros_cli):
    echo = spawn(sys.executable, '-m', 'zros.cli.main', 'topic', 'echo', '/x', 'std_msgs/msg/String', name='echo')
    result = zros_cli('topic', 'pub', '/x', 'std_msgs/msg/String', '{data: hi}', '--times', '3', '--rate', '20')
    assert result.returncode == 0, result
    echo.wait_for_output("data: hi\n---\ndata: hi\n---\ndata: hi\n---\n", timeout=5)
    time.sleep(0.2)
    assert echo.output().count('data: hi') == 3


def test_topic_echo_field_of_a_number(domain, context, zros_cli):
    """`--field` on a scalar prints the bare value and the separator on its own line."""
    node = Node('numbers', context=context)
    publisher = node.create_publisher(Int32, '/n', 10)
    stop = threading.Event()

    def publish():
        while not stop.is_set():
            publisher.publish(Int32(data=5))
            stop.wait(0.05)
    thread = threading.Thread(target=publish, daemon=True)
    thread.start()
    try:
        result = zros_cli('topic', 'echo', '/n', '--once', '--field', 'data')
    finally:
        stop.set()
        thread.join(5)
    assert result.returncode == 0, result
    assert result.stdout == '5\n---\n', result


def test_topic_echo_json_is_never_truncated_unless_asked(domain, context, zros_cli):
    """JSON is for programs: a 300-element float array and a 500-character string come out whole
    (ros2's YAML cut at 128 stays for the text output, and -l still cuts JSON when given)."""
    from zros.qos import DurabilityPolicy, QoSProfile
    from interfaces.std_msgs.msg import Float64MultiArray, MultiArrayDimension, MultiArrayLayout
    node = Node('long_arrays', context=context)
    latched = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL)
    publisher = node.create_publisher(Float64MultiArray, '/long', latched)
    data = [i * 0.5 for i in range(300)]
    label = 'x' * 500
    publisher.publish(Float64MultiArray(layout=MultiArrayLayout(dim=[MultiArrayDimension(label=label, size=300)]),
                                        data=data))
    import json
    as_json = zros_cli('topic', 'echo', '--json', '--once', '--timeout', '5', '/long')
    assert as_json.returncode == 0, as_json
    message = json.loads(as_json.stdout)
    assert message['data'] == data and message['layout']['dim'][0]['label'] == label, as_json
    cut = json.loads(zros_cli('topic', 'echo', '--json', '-l', '3', '--once', '--timeout', '5', '/long').stdout)
    assert cut['data'] == [0.0, 0.5, 1.0, '...'] and cut['layout']['dim'][0]['label'] == 'xxx...'
    as_yaml = zros_cli('topic', 'echo', '--once', '--timeout', '5', '/long')
    assert as_yaml.returncode == 0, as_yaml
    printed = yaml.safe_load(as_yaml.stdout.split('---')[0])
    assert printed['data'] == data[:128] + ['...'], as_yaml
    assert printed['layout']['dim'][0]['label'] == 'x' * 128 + '...', as_yaml


def test_topic_echo_timeout(domain, zros_cli):
    result = zros_cli('topic', 'echo', '/silent', 'std_msgs/msg/String', '--timeout', '0.3')
    assert_clean_failure(result, 'timed out', '/silent')


# -- interfaces ----------------------------------------------------------------------------------
def test_interface_show_nests_indented_fields(zros_cli):
    result = zros_cli('interface', 'show', 'geometry_msgs/msg/Twist')
    assert result.returncode == 0, result
    lines = result.stdout.splitlines()
    linear = next(i for i, line in enumerate(lines) if re.fullmatch(r'Vector3\s+linear', line))
    angular = next(i for i, line in enumerate(lines) if re.fullmatch(r'Vector3\s+angular', line))
    for start in (linear, angular):
        assert [line.split('#')[0].strip() for line in lines[start + 1:start + 4]] == \
            ['float64 x', 'float64 y', 'float64 z']
        assert all(line.startswith('\t') for line in lines[start + 1:start + 4])
    no_comments = zros_cli('interface', 'show', 'geometry_msgs/msg/Twist', '--no-comments')
    assert '#' not in no_comments.stdout
    assert no_comments.stdout.splitlines()[0].startswith('Vector3')


def test_interface_show_service_and_action(zros_cli):
    srv = zros_cli('interface', 'show', 'std_srvs/srv/SetBool')
    assert srv.returncode == 0, srv
    request, response = srv.stdout.split('\n---\n')
    assert 'bool data' in request and 'bool success' in response and 'string message' in response
    action = zros_cli('interface', 'show', 'action_tutorials_interfaces/action/Fibonacci')
    assert action.returncode == 0, action
    assert action.stdout.count('\n---\n') == 2


def test_interface_list_package_and_packages(zros_cli):
    listing = zros_cli('interface', 'list')
    assert listing.returncode == 0, listing
    lines = listing.stdout.splitlines()
    for heading, entry in (('Messages:', '    std_msgs/msg/String'), ('Services:', '    std_srvs/srv/Trigger'),
                           ('Actions:', '    action_tutorials_interfaces/action/Fibonacci')):
        assert heading in lines and entry in lines
        assert lines.index(heading) < lines.index(entry)
    only_msgs = zros_cli('interface', 'list', '-m').stdout
    assert 'Services:' not in only_msgs and '    geometry_msgs/msg/Twist' in only_msgs.splitlines()
    package = zros_cli('interface', 'package', 'std_srvs')
    assert package.stdout.splitlines() == ['std_srvs/srv/Empty', 'std_srvs/srv/SetBool', 'std_srvs/srv/Trigger']
    packages = zros_cli('interface', 'packages').stdout.splitlines()
    assert {'std_msgs', 'geometry_msgs', 'sensor_msgs', 'builtin_interfaces'} <= set(packages)


def test_interface_proto(zros_cli):
    result = zros_cli('interface', 'proto', 'geometry_msgs/msg/Twist')
    assert result.returncode == 0, result
    text = result.stdout.strip()
    assert text.startswith('"') and text.endswith('"')
    assert yaml.safe_load(text[1:-1]) == {'linear': {'x': 0.0, 'y': 0.0, 'z': 0.0},
                                          'angular': {'x': 0.0, 'y': 0.0, 'z': 0.0}}
    bare = zros_cli('interface', 'proto', 'std_srvs/srv/SetBool', '--no-quotes')
    assert yaml.safe_load(bare.stdout) == {'data': False}


# -- errors: one line on stderr, non-zero exit, no traceback ---------------------------------
def test_echo_unknown_topic_without_type(domain, zros_cli):
    assert_clean_failure(zros_cli('topic', 'echo', '/nobody_here'), '/nobody_here', 'type')


ERROR_CASES = [
    (('topic', 'pub', '/x', 'no_such_msgs/msg/Nope', '{}'), ('no_such_msgs/msg/Nope',)),
    (('topic', 'pub', '/x', 'std_msgs/msg/Nope', '{}'), ('std_msgs/msg/Nope',)),
    (('topic', 'pub', '/x', 'not a type', '{}'), ('not a type',)),
    (('topic', 'pub', '/x', 'std_msgs/msg/String', '{data: [}'), ('YAML',)),
    (('topic', 'pub', '/x', 'std_msgs/msg/String', '{nope: 1}'), ("'nope'",)),
    (('topic', 'pub', '/x', 'geometry_msgs/msg/Twist', '{linear: {w: 1}}'), ("'linear.w'",)),
    (('topic', 'pub', '/x', 'std_msgs/msg/Int32', '{data: 99999999999}'), ('data', 'range')),
    (('topic', 'pub', '/x', 'std_msgs/msg/Int32', '{data: abc}'), ('data',)),
    (('topic', 'pub', '/bad*name', 'std_msgs/msg/String', '{}'), ("'*'",)),
    (('topic', 'echo', '/x', 'std_msgs/msg/String', '--field', 'nope'), ("'nope'",)),
    (('topic', 'info', '/nobody_here'), ('/nobody_here',)),
    (('topic', 'type', '/nobody_here'), ('/nobody_here',)),
    (('node', 'info', '/nobody_here'), ('/nobody_here',)),
    (('interface', 'show', 'std_msgs/msg/Nope'), ('std_msgs/msg/Nope',)),
    (('interface', 'proto', 'nope'), ('nope',)),
    (('interface', 'package', 'no_such_pkg'), ('no_such_pkg',)),
    (('run', 'no_such_pkg', 'talker'), ('no_such_pkg',)),
    (('run', 'demo_nodes', 'no_such_exe'), ('no_such_exe', 'talker')),
    (('run', 'turtlesm', 'turtlesim_node'), ("Package 'turtlesm' not found. Did you mean 'turtlesim'?",)),
    (('run', 'turtlesim', 'turtlesim_nod'),
     ("No executable 'turtlesim_nod' found in package 'turtlesim'. Did you mean 'turtlesim_node'?",)),
    (('launch', 'turtlesm', 'multisim.launch.py'), ("package 'turtlesm' not found. Did you mean 'turtlesim'?",)),
    (('launch', 'turtlebot3_gazebo', 'empty_wrld.launch.py'),
     ("launch file 'empty_wrld.launch.py' not found in package 'turtlebot3_gazebo'. "
      "Did you mean 'empty_world.launch.py'?",)),
    (('pkg', 'executables', 'turtlesm'), ("Package 'turtlesm' not found. Did you mean 'turtlesim'?",)),
    (('run', 'demo_nodes', 'talker', '--ros-args', '--bogus'), ('--bogus',)),
    (('run', 'demo_nodes', 'talker', '--ros-args', '-r', 'chatter'), ('chatter',)),
    (('run', 'demo_nodes', 'talker', '--ros-args', '-r', '__node:=1x'), ('1x',)),
    (('run', 'demo_nodes', 'talker', '--ros-args', '-r'), ('-r',)),
]


@pytest.mark.parametrize('args, fragments', ERROR_CASES, ids=[' '.join(args) for args, _ in ERROR_CASES])
def test_errors_are_one_clean_line(domain, zros_cli, args, fragments):
    assert_clean_failure(zros_cli(*args, timeout=10), *fragments)


def test_usage_errors_exit_non_zero(zros_cli):
    result = zros_cli('topic', 'echo')  # missing argument: argparse's usage message
    assert result.returncode == 2 and 'Traceback' not in result.stderr
    assert zros_cli('nosuchverb').returncode == 2


# -- help ----------------------------------------------------------------------------------------
def test_help(zros_cli):
    result = zros_cli('--help')
    assert result.returncode == 0, result
    for verb in ('run', 'topic', 'node', 'interface'):
        assert verb in result.stdout
    assert zros_cli().returncode == 0
    version = zros_cli('--version')
    assert version.returncode == 0 and version.stdout.startswith('zros ')


@pytest.mark.parametrize('verb', ['run', 'topic', 'node', 'interface'])
def test_verb_help(zros_cli, verb):
    result = zros_cli(verb, '-h')
    assert result.returncode == 0, result
    assert 'usage' in result.stdout.lower()
    assert result.stderr == ''


@pytest.mark.parametrize('args', [
    ('topic', 'list', '-h'), ('topic', 'echo', '-h'), ('topic', 'pub', '-h'), ('topic', 'info', '-h'),
    ('topic', 'type', '-h'), ('topic', 'find', '-h'), ('node', 'list', '-h'), ('node', 'info', '-h'),
    ('interface', 'list', '-h'), ('interface', 'show', '-h'), ('interface', 'proto', '-h'),
    ('interface', 'package', '-h'), ('interface', 'packages', '-h'), ('topic',), ('node',), ('interface',),
], ids=' '.join)
def test_sub_verb_help(capsys, args):
    """Sub-verb help, through the CLI's entry function in this process (argparse exits 0)."""
    from zros.cli.main import main
    with pytest.raises(SystemExit) as exited:
        main(list(args))
    assert exited.value.code == 0
    out, err = capsys.readouterr()
    assert out.lower().startswith('usage: zros ' + args[0])
    assert err == ''
