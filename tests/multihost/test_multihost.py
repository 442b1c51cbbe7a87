"""zros across hosts: three network namespaces on one switch (see conftest.py).

h1 runs the router, h2 the robot's nodes, h3 the laptop's listener and CLI; every process
reaches the others only through the 10.123.0.0/24 network those namespaces share.
"""
from __future__ import annotations

import re
import sys
import time
from pathlib import Path

import pytest

from .conftest import REPO, ROUTER, Net, wait_until

HERE = Path(__file__).resolve().parent
CONFIGS = REPO / 'configs' / 'zenoh'
MAIN = f'tcp/{ROUTER}:7447'

pytestmark = pytest.mark.timeout(90)


def seqs(proc) -> list[int]:
    return [int(m) for m in re.findall(r'^got (\d+)$', proc.output(), re.M)]


def published(proc) -> int:
    found = re.findall(r'^published (\d+)$', proc.output(), re.M)
    return int(found[-1]) if found else 0


# -- one system for the basic tests: router h1, nodes h2, listener h3 ---------------------------
@pytest.fixture(scope='module')
def system(net: Net):
    router = net.h1.zros_bg('router', '-v', name='router')
    router.wait_for('listening on tcp/0.0.0.0:7447')
    talker = net.h2.zros_bg('run', 'demo_nodes', 'talker', name='talker', ZROS_CONNECT=MAIN)
    server = net.h2.zros_bg('run', 'demo_nodes', 'add_two_ints_server', name='server', ZROS_CONNECT=MAIN)
    actions = net.h2.zros_bg('run', 'demo_nodes', 'fibonacci_action_server', '--ros-args', '-p', 'step_period:=0.05',
                             name='fibonacci', ZROS_CONNECT=MAIN)
    # The listener is given its endpoint as a `zros run` option rather than the environment.
    listener = net.h3.zros_bg('run', '--connect', MAIN, 'demo_nodes', 'listener', name='listener')
    yield {'router': router, 'talker': talker, 'server': server, 'actions': actions, 'listener': listener}
    net.kill_all([router, talker, server, actions, listener])


def test_router_prints_where_it_listens(system):
    out = system['router'].output()
    assert 'listening on tcp/0.0.0.0:7447' in out
    assert f'reachable at tcp/{ROUTER}:7447' in out


def test_pubsub_across_hosts(system):
    system['listener'].wait_for('I heard: [Hello World', timeout=20)


def test_node_list_across_hosts(net, system):
    expected = {'/talker', '/add_two_ints_server', '/fibonacci_action_server', '/listener'}
    result = None

    def complete():
        nonlocal result
        result = net.h3.zros('node', 'list', ZROS_CONNECT=MAIN)
        return result.returncode == 0 and expected <= set(result.stdout.split())
    wait_until(complete, 20, lambda: f'all nodes in `zros node list`: {result!r}')
    # A fresh CLI process gets the complete graph at once, from the router (no settling wait).
    again = net.h3.zros('node', 'list', ZROS_CONNECT=MAIN)
    assert expected <= set(again.stdout.split()), again
    assert again.seconds < 5.0, again
    # That is the router's graph service, which any Zenoh program can ask.
    graph = net.h3.spawn(sys.executable, HERE / 'plain_client.py', 'get', MAIN, '@zros/v1/0/graph', name='graph-get')
    out = graph.wait_for('reply', timeout=15)
    assert '/NN/%/talker' in out and '/SS/%/add_two_ints_server/%add_two_ints/' in out, out
    net.kill_all([graph])
    topics = net.h3.zros('topic', 'list', '-t', ZROS_CONNECT=MAIN)
    assert '/chatter [std_msgs/msg/String]' in topics.stdout, topics


def test_service_call_across_hosts(net, system):
    result = net.h3.zros('service', 'call', '/add_two_ints', 'example_interfaces/srv/AddTwoInts', '{a: 2, b: 40}',
                         '--timeout', '15', ZROS_CONNECT=MAIN, timeout=30)
    assert result.returncode == 0, result
    assert 'AddTwoInts_Response(sum=42)' in result.stdout, result


def test_action_across_hosts(net, system):
    result = net.h3.zros('action', 'send_goal', '/fibonacci', 'action_tutorials_interfaces/action/Fibonacci',
                         '{order: 5}', '--timeout', '15', ZROS_CONNECT=MAIN, timeout=40)
    assert result.returncode == 0, result
    assert 'Goal accepted with ID' in result.stdout, result
    assert 'SUCCEEDED' in result.stdout, result
    assert re.search(r'0\D+1\D+1\D+2\D+3\D+5', result.stdout), result


def test_parameters_across_hosts(net, system):
    result = net.h3.zros('param', 'set', '/fibonacci_action_server', 'step_period', '0.02', ZROS_CONNECT=MAIN)
    assert result.returncode == 0 and 'Set parameter successful' in result.stdout, result
    result = net.h3.zros('param', 'get', '/fibonacci_action_server', 'step_period', ZROS_CONNECT=MAIN)
    assert result.returncode == 0 and 'Double value is: 0.02' in result.stdout, result


def test_plain_zenoh_client_through_the_router(net, system):
    """A plain Zenoh client (rmw_zenoh #929) gets zros data through `zros router`."""
    client = net.h3.spawn(sys.executable, HERE / 'plain_client.py', 'sub', MAIN, 'zros/0/t/chatter', name='plain')
    try:
        client.wait_for("sample ['Hello World", timeout=15)
    finally:
        net.kill_all([client])


def test_transient_local_late_joiner_across_hosts(net, system, procs):
    latched = net.h2.zros_bg('topic', 'pub', '--qos-durability', 'transient_local', '--qos-depth', '1', '-1',
                             '--keep-alive', '60', '/latched', 'std_msgs/msg/String', '{data: latched-42}',
                             name='latched', ZROS_CONNECT=MAIN)
    latched.wait_for('publishing #1')
    time.sleep(1.0)   # the subscriber below joins after the only sample was published
    result = net.h3.zros('topic', 'echo', '--qos-durability', 'transient_local', '--once', '--timeout', '15',
                         '/latched', 'std_msgs/msg/String', ZROS_CONNECT=MAIN, timeout=30)
    assert result.returncode == 0, result
    assert 'latched-42' in result.stdout, result


def test_domains_are_isolated_on_one_router(net, system, procs):
    other = net.h2.zros_bg('topic', 'pub', '-r', '10', '/chatter', 'std_msgs/msg/String', '{data: from-domain-5}',
                           name='domain5-pub', domain=5, ZROS_CONNECT=MAIN)
    other.wait_for('publishing #1')
    echo = net.h3.zros('topic', 'echo', '--once', '--timeout', '15', '/chatter', 'std_msgs/msg/String',
                       domain=5, ZROS_CONNECT=MAIN, timeout=30)
    assert 'from-domain-5' in echo.stdout, echo            # domain 5 works through the router...
    nodes5 = net.h3.zros('node', 'list', domain=5, ZROS_CONNECT=MAIN)
    assert '/talker' not in nodes5.stdout and '/listener' not in nodes5.stdout, nodes5
    services5 = net.h3.zros('service', 'list', domain=5, ZROS_CONNECT=MAIN)
    assert '/add_two_ints' not in services5.stdout, services5
    nodes0 = net.h3.zros('node', 'list', ZROS_CONNECT=MAIN)
    assert '/talker' in nodes0.stdout and not any('zros_cli' in n for n in nodes0.stdout.split()), nodes0
    time.sleep(0.5)
    assert 'from-domain-5' not in system['listener'].output()   # ...and never reaches domain 0


def test_graph_through_a_bare_zenoh_router(net, procs):
    """`fetch_entities` without a zros hub or `zros router`: the readers' own token collection."""
    router = net.h1.spawn(sys.executable, HERE / 'bare_router.py', f'tcp/{ROUTER}:7450', name='bare-router')
    router.wait_for('router up')
    endpoint = f'tcp/{ROUTER}:7450'
    net.h2.zros_bg('run', 'demo_nodes', 'talker', name='bare-talker', domain=7, ZROS_CONNECT=endpoint) \
        .wait_for('Publishing')
    result = net.h3.zros('node', 'list', domain=7, ZROS_CONNECT=endpoint)
    assert result.stdout.split() == ['/talker'], result
    echo = net.h3.zros('topic', 'echo', '--once', '--timeout', '10', '/chatter', domain=7, ZROS_CONNECT=endpoint)
    assert 'Hello World' in echo.stdout, echo


def test_subnet_discovery_without_router(net, procs):
    """ZROS_DISCOVERY=subnet: multicast scouting on the namespaces' own LAN, no router at all."""
    net.h2.zros_bg('run', 'demo_nodes', 'talker', name='subnet-talker', domain=13, ZROS_DISCOVERY='subnet') \
        .wait_for('Publishing')
    echo = net.h3.zros('topic', 'echo', '--once', '--timeout', '15', '/chatter', 'std_msgs/msg/String',
                       domain=13, ZROS_DISCOVERY='subnet', timeout=30)
    assert 'Hello World' in echo.stdout, echo


def test_robot_runs_the_router_and_nodes_without_settings(net, procs):
    """The issue's story: on the robot `zros router`, and nodes started with no setting at all;
    the laptop sets ZROS_CONNECT to the robot. The laptop here cannot be dialled (it listens on
    loopback only, as behind NAT), so its CLI must dial the robot's talker: which works because
    the talker, finding a router on domain 0's hub port, listens on every interface."""
    robot = f'tcp/{net.h2.address}:7447'
    net.h2.zros_bg('router', name='robot-router').wait_for('listening on')
    net.h2.zros_bg('run', 'demo_nodes', 'talker', '--ros-args', '-r', '__node:=robot_talker',
                   name='robot-talker').wait_for('Publishing')
    nodes = net.h3.zros('node', 'list', ZROS_CONNECT=robot)
    assert nodes.stdout.split() == ['/robot_talker'], nodes
    echo = net.h3.zros('topic', 'echo', '--once', '--timeout', '10', '/chatter', 'std_msgs/msg/String',
                       ZROS_CONNECT=robot, ZROS_LISTEN='tcp/127.0.0.1:0')
    assert 'Hello World' in echo.stdout, echo


def test_launch_with_router_and_launch_with_connect(net, procs):
    """`zros launch --router` on the robot; `zros launch --connect` on the laptop."""
    launch_file = REPO / 'configs' / 'talker_listener.launch.yaml'
    robot = net.h2.zros_bg('launch', '--router', launch_file, 'topic:=robot_news', name='robot-launch', domain=21)
    robot.wait_for('I heard: [Hello World', timeout=20)
    assert f'[router] reachable at tcp/{net.h2.address}:7447' in robot.output()
    laptop = net.h3.zros_bg('launch', launch_file, 'topic:=laptop_news', '--connect', f'tcp/{net.h2.address}:7447',
                            name='laptop-launch', domain=21)
    laptop.wait_for('I heard: [Hello World', timeout=20)
    # The laptop's talker is heard on the robot, through the launch's router.
    echo = net.h2.zros('topic', 'echo', '--once', '--timeout', '10', '/laptop_news', 'std_msgs/msg/String',
                       domain=21, ZROS_CONNECT='tcp/127.0.0.1:7447')
    assert 'Hello World' in echo.stdout, echo
    wait_until(lambda: {'/robot_news', '/laptop_news'} <= set(
        net.h3.zros('topic', 'list', domain=21, ZROS_CONNECT=f'tcp/{net.h2.address}:7447').stdout.split()),
        15, 'both launches\' topics in the graph')


# -- resilience --------------------------------------------------------------------------------
def test_router_restart(net, procs):
    endpoint = f'tcp/{ROUTER}:7460'
    router = net.h1.zros_bg('router', '--listen', endpoint, name='router-a')
    router.wait_for('listening on')
    pub = net.h2.spawn(sys.executable, HERE / 'seqnode.py', 'pub', 'seqpub', name='seqpub', domain=9,
                       ZROS_CONNECT=endpoint)
    sub = net.h3.spawn(sys.executable, HERE / 'seqnode.py', 'sub', 'seqsub', name='seqsub', domain=9,
                       ZROS_CONNECT=endpoint)
    wait_until(lambda: len(seqs(sub)) >= 10, 20, lambda: f'samples before the restart: {sub.output()[-500:]}')
    net.kill_all([router])
    before = len(seqs(sub))
    # The peers are linked to each other directly: they keep talking without the router.
    wait_until(lambda: len(seqs(sub)) >= before + 20, 10, 'samples while the router is down')
    router = net.h1.zros_bg('router', '--listen', endpoint, name='router-b')
    router.wait_for('listening on')
    # New nodes join when it is back: a new talker on the laptop, heard on the robot...
    net.h3.zros_bg('run', 'demo_nodes', 'talker', name='late-talker', domain=9, ZROS_CONNECT=endpoint) \
        .wait_for('Publishing')
    echo = net.h2.zros('topic', 'echo', '--once', '--timeout', '15', '/chatter', 'std_msgs/msg/String',
                       domain=9, ZROS_CONNECT=endpoint, timeout=30)
    assert 'Hello World' in echo.stdout, echo
    # ...and the graph through the new router has every node, old and new.
    wait_until(lambda: {'/seqpub', '/seqsub', '/talker'} <= set(
        net.h2.zros('node', 'list', domain=9, ZROS_CONNECT=endpoint).stdout.split()), 15, 'the whole graph')
    got = seqs(sub)
    assert got == list(range(got[0], got[0] + len(got))), 'a reliable topic lost samples across the restart'


def test_short_link_outage_loses_nothing(net, procs):
    """Cable out for 2 s (well within Zenoh's 10 s lease): TCP and Zenoh's queues hold the
    samples, and the reliable topic delivers every one, in order, when the cable is back."""
    endpoint = f'tcp/{ROUTER}:7465'
    net.h1.zros_bg('router', '--listen', endpoint, name='router-link').wait_for('listening on')
    pub = net.h2.spawn(sys.executable, HERE / 'seqnode.py', 'pub', 'seqpub', name='seqpub', domain=11,
                       ZROS_CONNECT=endpoint)
    sub = net.h3.spawn(sys.executable, HERE / 'seqnode.py', 'sub', 'seqsub', name='seqsub', domain=11,
                       ZROS_CONNECT=endpoint)
    wait_until(lambda: len(seqs(sub)) >= 10, 20, lambda: f'samples before the outage: {sub.output()[-500:]}')
    net.link(net.h3, up=False)
    try:
        time.sleep(0.5)
        during = len(seqs(sub))
        time.sleep(1.5)
        assert len(seqs(sub)) <= during + 1, 'samples arrived through an unplugged cable'
        sent_while_down = published(pub)
    finally:
        net.link(net.h3, up=True)
    wait_until(lambda: seqs(sub) and seqs(sub)[-1] >= sent_while_down + 10, 15, 'delivery after the outage')
    got = seqs(sub)
    assert got == list(range(got[0], got[-1] + 1)), f'lost or reordered samples: {sorted(set(range(got[0], got[-1])) - set(got))[:20]}'


def test_large_arrays_across_hosts_without_shared_memory(net, procs):
    """4 MB images from a publisher with shared memory to a subscriber on another host with
    none: Zenoh copies the shared-memory payloads into the network messages, bit-exact."""
    endpoint = f'tcp/{ROUTER}:7467'
    net.h1.zros_bg('router', '--listen', endpoint, name='router-big').wait_for('listening on')
    sub = net.h3.spawn(sys.executable, HERE / 'bigarray.py', 'sub', name='bigsub', domain=13, ZROS_CONNECT=endpoint,
                       ZROS_SHM_POOL_SIZE='0')
    sub.wait_for('subscribed')
    pub = net.h2.spawn(sys.executable, HERE / 'bigarray.py', 'pub', '5', name='bigpub', domain=13,
                       ZROS_CONNECT=endpoint)

    def lines(proc, word):
        return re.findall(rf'^{word} (\d+ \w+)$', proc.output(), re.M)
    # The publisher prints each image's line after publishing it, so the subscriber's line can
    # come first: wait for both.
    wait_until(lambda: len(lines(sub, 'got')) >= 5 and len(lines(pub, 'published')) >= 5, 40,
               lambda: f'received: {sub.output()[-800:]}\npublished: {pub.output()[-800:]}')
    assert lines(sub, 'got') == lines(pub, 'published')


def test_dropped_link_resumes(net, procs, tmp_path):
    """Cable out for longer than the lease (1 s here, by config): Zenoh closes the links, the
    samples of the outage are lost, and delivery resumes by itself when the cable is back."""
    lease = tmp_path / 'lease.json5'
    lease.write_text('{ transport: { link: { tx: { lease: 1000, keep_alive: 4 } } } }\n')
    endpoint = f'tcp/{ROUTER}:7466'
    net.h1.zros_bg('router', '--listen', endpoint, '--config', lease, name='router-lease').wait_for('listening on')
    pub = net.h2.spawn(sys.executable, HERE / 'seqnode.py', 'pub', 'seqpub', name='seqpub', domain=12,
                       ZROS_CONNECT=endpoint, ZROS_CONFIG=str(lease))
    sub = net.h3.spawn(sys.executable, HERE / 'seqnode.py', 'sub', 'seqsub', name='seqsub', domain=12,
                       ZROS_CONNECT=endpoint, ZROS_CONFIG=str(lease))
    wait_until(lambda: len(seqs(sub)) >= 10, 20, lambda: f'samples before the outage: {sub.output()[-500:]}')
    net.link(net.h3, up=False)
    try:
        time.sleep(3.0)
        sent_while_down = published(pub)
    finally:
        net.link(net.h3, up=True)
    wait_until(lambda: seqs(sub) and seqs(sub)[-1] >= sent_while_down + 20, 20, 'delivery after the link returned')
    assert pub.alive() and sub.alive()


# -- TLS, mutual TLS, access control -------------------------------------------------------------
@pytest.fixture(scope='module')
def keystore(net, tmp_path_factory) -> Path:
    """`zros security create-keys` as a user runs it: keys/ for the example configs' relative
    paths, and a second CA's keys for a client the routers must refuse."""
    root = tmp_path_factory.mktemp('tls')
    made = net.h1.zros('security', 'create-keys', root / 'keys', '--nodes', 'router,client,teleop,camera',
                       '--hosts', ROUTER, '--days', '2')
    assert made.returncode == 0, made
    rogue = net.h1.zros('security', 'create-keys', root / 'rogue', '--nodes', 'client', '--hosts', ROUTER)
    assert rogue.returncode == 0, rogue
    return root


def _tls_router(net, keystore, config: str, port: int, name: str):
    router = net.h1.zros_bg('router', '--config', CONFIGS / config, '--listen', f'tls/{ROUTER}:{port}',
                            name=name, cwd=keystore)
    router.wait_for('listening on')
    return router, f'tls/{ROUTER}:{port}'


def test_tls_router_refuses_plain_tcp(net, keystore, procs):
    router, endpoint = _tls_router(net, keystore, 'tls-router.json5', 7471, 'tls-router')
    net.h2.zros_bg('run', 'demo_nodes', 'talker', name='tls-talker', domain=0, cwd=keystore,
                   ZROS_CONFIG=str(CONFIGS / 'tls-client.json5'), ZROS_CONNECT=endpoint).wait_for('Publishing')
    ok = net.h3.zros('node', 'list', cwd=keystore, ZROS_CONFIG=str(CONFIGS / 'tls-client.json5'),
                     ZROS_CONNECT=endpoint)
    assert ok.stdout.split() == ['/talker'], ok
    plain = net.h3.zros('node', 'list', ZROS_CONNECT=f'tcp/{ROUTER}:7471')
    assert plain.stdout.strip() == '', plain
    assert 'cannot reach' in plain.stderr, plain
    echo = net.h3.zros('topic', 'echo', '--once', '--timeout', '3', '/chatter', 'std_msgs/msg/String',
                       ZROS_CONNECT=f'tcp/{ROUTER}:7471')
    assert echo.returncode != 0 and 'Hello World' not in echo.stdout, echo


def test_mutual_tls_refuses_clients_without_a_valid_certificate(net, keystore, procs):
    router, endpoint = _tls_router(net, keystore, 'mtls-router.json5', 7472, 'mtls-router')
    good = net.h3.zros('node', 'list', cwd=keystore, ZROS_CONFIG=str(CONFIGS / 'mtls-client.json5'),
                       ZROS_CONNECT=endpoint)
    assert good.returncode == 0, good
    no_cert = net.h3.zros('node', 'list', cwd=keystore, ZROS_CONFIG=str(CONFIGS / 'tls-client.json5'),
                          ZROS_CONNECT=endpoint)
    assert no_cert.returncode == 1 and 'cannot open the Zenoh session' in no_cert.stderr, no_cert
    other_ca = net.h3.zros('node', 'list', cwd=keystore, ZROS_CONFIG=str(keystore / 'rogue/enclaves/client/tls.json5'),
                           ZROS_CONNECT=endpoint)
    assert other_ca.returncode == 1 and 'cannot open the Zenoh session' in other_ca.stderr, other_ca


def test_acl_denies_a_publish(net, keystore, procs):
    router, endpoint = _tls_router(net, keystore, 'acl-router.json5', 7473, 'acl-router')
    echo = net.h3.zros_bg('topic', 'echo', '/cmd_vel', 'geometry_msgs/msg/Twist', '--field', 'linear.x',
                          name='cmd-echo', cwd=keystore, ZROS_CONFIG=str(CONFIGS / 'mtls-client.json5'),
                          ZROS_CONNECT=endpoint)

    def publish(node: str, x: float):
        return net.h2.zros('topic', 'pub', '-t', '5', '-r', '10', '-w', '1', '/cmd_vel', 'geometry_msgs/msg/Twist',
                           f'{{linear: {{x: {x}}}}}', cwd=keystore,
                           ZROS_CONFIG=str(keystore / f'keys/enclaves/{node}/tls.json5'), ZROS_CONNECT=endpoint)
    denied = publish('camera', 9.5)
    assert denied.returncode == 0, denied      # the publisher is not told: the router drops its samples
    allowed = publish('teleop', 1.5)
    assert allowed.returncode == 0, allowed
    wait_until(lambda: '1.5' in echo.output(), 10, lambda: f'teleop\'s samples: {echo.output()}')
    assert '9.5' not in echo.output(), echo.output()
