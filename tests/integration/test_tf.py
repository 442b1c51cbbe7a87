"""TF2 across processes: a broadcaster in one process, listeners in another; static transforms
for late joiners; static_transform_publisher's two argument forms; tf2_echo's output.

The broadcaster script plays the TF2 tutorial's turtle: `turtle1` moves in `world` with a
pose that is a known function of its stamp, so interpolated lookups can be checked exactly.
"""
from __future__ import annotations

import math
import time

import pytest

from conftest import wait_until

T0 = 1000.0       # stamp of sample 0 [s]
STEP = 0.05       # between samples [s]

TURTLE_BROADCASTER = f'''
import math, sys, time
import zros
from zros.node import Node
from zros.tf2_ros import TransformBroadcaster, StaticTransformBroadcaster
from zros.tf_transformations import quaternion_from_euler
from interfaces.geometry_msgs.msg import TransformStamped

def stamped(parent, child, sec, x, y, yaw):
    t = TransformStamped()
    t.header.stamp.sec, t.header.stamp.nanosec = int(sec), int(round((sec - int(sec)) * 1e9))
    t.header.frame_id, t.child_frame_id = parent, child
    t.transform.translation.x, t.transform.translation.y = x, y
    q = quaternion_from_euler(0, 0, yaw)
    t.transform.rotation.x, t.transform.rotation.y, t.transform.rotation.z, t.transform.rotation.w = map(float, q)
    return t

with zros.init():
    node = Node('turtle_tf2_broadcaster')
    static = StaticTransformBroadcaster(node)
    static.sendTransform(stamped('turtle1', 'carrot1', 0, -1.0, 0.0, 0.0))   # two separate calls:
    static.sendTransform(stamped('sea', 'island', 0, 0.0, 0.0, 0.0))         # both must survive
    tf = TransformBroadcaster(node)
    k = 0
    print('broadcasting', flush=True)
    while zros.ok():
        tf.sendTransform(stamped('world', 'turtle1', {T0} + k * {STEP}, 0.1 * k, 0.02 * k, 0.03 * k))
        k += 1
        time.sleep(0.01)
'''


def _pose(t) -> tuple[float, float, float]:
    tr, q = t.transform.translation, t.transform.rotation
    return tr.x, tr.y, 2 * math.atan2(q.z, q.w)


@pytest.fixture
def listener(make_context):
    from zros.node import Node
    from zros.tf2_ros import Buffer, TransformListener
    node = Node('turtle_tf2_listener', context=make_context())
    buffer = Buffer(node=node)
    TransformListener(buffer, node)
    return node, buffer


def test_listener_in_another_process_looks_up_latest_past_and_fails_clearly(spawn, listener):
    from zros.tf2_ros import (ConnectivityException, Duration, ExtrapolationException, LookupException, Time,
                              TransformException)
    node, buffer = listener
    spawn.script(TURTLE_BROADCASTER, name='broadcaster').wait_for_output('broadcasting', timeout=20)
    assert buffer.can_transform('world', 'carrot1', Time(), timeout=Duration(seconds=10))
    wait_until(lambda: buffer.lookup_transform('world', 'turtle1', Time()).header.stamp.sec >= T0 + 0.5, 10,
               message='half a second of turtle poses')
    latest = buffer.lookup_transform('world', 'turtle1', Time())
    k = round((latest.header.stamp.sec + latest.header.stamp.nanosec / 1e9 - T0) / STEP)
    assert _pose(latest) == pytest.approx((0.1 * k, 0.02 * k, 0.03 * k), abs=1e-9)
    # a past time halfway between two samples: translation and yaw interpolated linearly
    mid = k - 4.5
    past = buffer.lookup_transform('world', 'turtle1', Time(seconds=T0 + mid * STEP))
    assert _pose(past) == pytest.approx((0.1 * mid, 0.02 * mid, 0.03 * mid), abs=1e-6)
    # the carrot 1 m behind the turtle, through the chain world -> turtle1 -> carrot1
    carrot = buffer.lookup_transform('world', 'carrot1', Time(seconds=T0 + mid * STEP))
    yaw = 0.03 * mid
    assert _pose(carrot)[:2] == pytest.approx((0.1 * mid - math.cos(yaw), 0.02 * mid - math.sin(yaw)), abs=1e-6)
    with pytest.raises(ExtrapolationException, match='extrapolation into the future'):
        buffer.lookup_transform('world', 'turtle1', Time(seconds=T0 + 10_000))
    with pytest.raises(LookupException, match='Frames that exist: carrot1, island, sea, turtle1, world'):
        buffer.lookup_transform('world', 'turtle9', Time())
    with pytest.raises(ConnectivityException):
        buffer.lookup_transform('world', 'island', Time())
    assert issubclass(ExtrapolationException, TransformException)
    # the node's tf2_frames service answers with the frames as YAML (what view_frames reads)
    import yaml
    from interfaces.tf2_msgs.srv import FrameGraph
    from zros.executors import SingleThreadedExecutor
    executor = SingleThreadedExecutor(context=node.context)
    executor.add_node(node)
    future = node.create_client(FrameGraph, 'tf2_frames').call_async(FrameGraph.Request())
    executor.spin_until_future_complete(future, timeout_sec=10)
    frames = yaml.safe_load(future.result().frame_yaml)
    assert frames['turtle1']['parent'] == 'world' and frames['carrot1']['parent'] == 'turtle1'
    assert frames['turtle1']['rate'] == pytest.approx(1 / STEP, rel=0.1)


def test_every_buffer_serves_tf2_frames_without_a_warning(make_context, capfd):
    """Each node holding a Buffer serves tf2_frames, as in ROS: a Nav2 stack has several, and
    no 'already served' warning is logged for them (other services still get one)."""
    from zros.graph import EntityKind
    from zros.node import Node
    from zros.tf2_ros import Buffer
    first, second = Node('planner', context=make_context()), Node('controller', context=make_context())
    Buffer(node=first)
    wait_until(lambda: any(e.kind == EntityKind.SERVICE and e.name == '/tf2_frames'
                           for e in second.context.graph.entities()), 10, message='the first tf2_frames server')
    assert Buffer(node=second).srv.service_name == '/tf2_frames'
    assert 'already served' not in capfd.readouterr().err

def test_static_frames_reach_a_late_listener_and_listeners_share_one_subscription(spawn, make_context):
    from zros.node import Node
    from zros.tf2_ros import Buffer, Time, TransformListener
    from zros.tf2_ros.listener_hub import TfHub
    spawn.script(TURTLE_BROADCASTER, name='broadcaster').wait_for_output('broadcasting', timeout=20)
    time.sleep(0.5)  # the static frames were sent before this process listened
    context = make_context()
    first, second = Node('first', context=context), Node('second', context=context)
    buffers = [Buffer(), Buffer()]
    TransformListener(buffers[0], first)
    for buffer in buffers[:1]:
        assert buffer.can_transform('turtle1', 'carrot1', Time(), timeout=10)
        assert buffer.can_transform('sea', 'island', Time(), timeout=10)
    # a listener made later in the same process gets the static frames at once from the hub
    TransformListener(buffers[1], second)
    assert buffers[1].can_transform('turtle1', 'carrot1', Time()) and buffers[1].can_transform('sea', 'island', Time())
    assert buffers[1].can_transform('world', 'turtle1', Time(), timeout=5)
    hub = TfHub.for_context(context)
    assert len(hub._subscribers) == 2 and len(hub._targets[False]) == 2
    # both nodes show up as /tf subscribers in the graph
    wait_until(lambda: sorted(e.node_name for e in second.get_subscriptions_info_by_topic('/tf')
                              if e.node_name in ('first', 'second')) == ['first', 'second'], 5,
               message='both listeners in the graph')
    second.destroy_node()
    assert len(hub._targets[False]) == 1 and len(hub._subscribers) == 2


def test_a_listener_message_is_work_for_spin_once_and_follows_a_new_buffer(make_context):
    """rclpy code sends a transform, then `spin_once()`s to let its own listener take it (tf2_ros's
    tests do): the message counts as the listener's callback. Assigning `listener.buffer` moves
    the feed to the new buffer."""
    from zros.executors import SingleThreadedExecutor
    from zros.node import Node
    from zros.tf2_ros import Buffer, Time, TransformBroadcaster, TransformListener
    from interfaces.geometry_msgs.msg import TransformStamped
    context = make_context()
    node = Node('loopback_tf', context=context)
    listener = TransformListener(Buffer(), node)
    broadcaster = TransformBroadcaster(node)
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(node)
    wait_until(lambda: broadcaster.pub_tf.get_subscription_count() > 0, 5, message='the listener matched')
    fresh = Buffer()
    listener.buffer = fresh
    transform = TransformStamped()
    transform.header.frame_id, transform.child_frame_id = 'foo', 'bar'
    transform.header.stamp.sec = 1
    transform.transform.translation.x, transform.transform.rotation.w = 42.0, 1.0
    broadcaster.sendTransform(transform)
    import threading
    spinner = threading.Thread(target=executor.spin_once, daemon=True)   # no timeout, as rclpy code calls it
    spinner.start()
    spinner.join(10)
    assert not spinner.is_alive(), 'spin_once is still waiting: the message was not work for it'
    assert fresh.lookup_transform('foo', 'bar', Time(seconds=1)).transform.translation.x == 42.0
    executor.shutdown()


def test_buffer_server_answers_buffer_client_lookups(spawn, make_context):
    from zros.executors import SingleThreadedExecutor
    from zros.node import Node
    from zros.tf2_ros import Duration, LookupException, Time
    from zros.tf2_ros.buffer_client import BufferClient
    spawn.node('tf2_ros', 'static_transform_publisher', '--x', '1', '--frame-id', 'odom', '--child-frame-id', 'base')
    spawn.node('tf2_ros', 'buffer_server')
    context = make_context()
    node = Node('remote_lookup', context=context)
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(node)
    import threading
    threading.Thread(target=lambda: _spin_quietly(executor), daemon=True).start()
    client = BufferClient(node, 'tf2_buffer_server')
    transform = client.lookup_transform('odom', 'base', Time(), Duration(seconds=10))
    assert transform.transform.translation.x == 1.0
    assert client.can_transform('odom', 'base', Time())
    with pytest.raises(LookupException):
        client.lookup_transform('odom', 'nowhere', Time(), Duration(seconds=0.2))
    assert not client.can_transform('nowhere', 'base', Time())
    client.destroy()
    executor.shutdown()


def _spin_quietly(executor) -> None:
    try:
        executor.spin()
    except Exception:  # noqa: BLE001 - ends with the executor
        pass


def test_static_transform_publisher_both_forms_and_tf2_echo(spawn, zros_cli):
    spawn.node('tf2_ros', 'static_transform_publisher', '--x', '1', '--y', '2', '--z', '0.5', '--yaw', '1.5707963267948966',
               '--frame-id', 'base_link', '--child-frame-id', 'laser').wait_for_output('Spinning until stopped')
    old = spawn.node('tf2_ros', 'static_transform_publisher', '0.1', '0', '0', '0', '0', '0', '1', 'laser', 'lens')
    old.wait_for_output("from 'laser' to 'lens'")
    assert 'Old-style arguments are deprecated' in old.output()
    assert "rotation: ('0.000000', '0.000000', '0.000000', '1.000000')" in old.output()
    echo = spawn.node('tf2_ros', 'tf2_echo', 'base_link', 'lens', '10')
    out = echo.wait_for_output('- Matrix:', timeout=20)
    block = out[out.index('At time'):]
    lines = block.splitlines()[:10]
    assert lines[1:6] == ['- Translation: [1.000, 2.100, 0.500]',
                          '- Rotation: in Quaternion [0.000, 0.000, 0.707, 0.707]',
                          '- Rotation: in RPY (radian) [0.000, -0.000, 1.571]',
                          '- Rotation: in RPY (degree) [0.000, -0.000, 90.000]',
                          '- Matrix:'], block
    assert lines[6:10] == ['  0.000 -1.000  0.000  1.000', '  1.000  0.000  0.000  2.100',
                           '  0.000  0.000  1.000  0.500', '  0.000  0.000  0.000  1.000'], block
    bad = zros_cli('run', 'tf2_ros', 'static_transform_publisher', '--x', 'one', '--frame-id', 'a', '--child-frame-id', 'b')
    assert bad.returncode == 1 and 'Failed to parse --x argument as float' in bad.stderr
    assert len(bad.stderr.strip().splitlines()) == 1 and 'Traceback' not in bad.stderr
    bad = zros_cli('run', 'tf2_ros', 'static_transform_publisher', '--frame-id', 'a')
    assert bad.returncode == 1 and 'Child frame id must not be empty' in bad.stderr


def test_non_normalised_quaternion_is_normalised_and_warned_once(spawn):
    spawn.node('tf2_ros', 'static_transform_publisher', '--qz', '1', '--qw', '1', '--frame-id', 'a',
               '--child-frame-id', 'b').wait_for_output('Spinning until stopped')
    echo = spawn.node('tf2_ros', 'tf2_echo', 'a', 'b', '20')
    wait_until(lambda: echo.output().count('- Matrix:') >= 3, 20, message=lambda: f'three echoes:\n{echo.output()}')
    out = echo.output()
    assert '- Rotation: in Quaternion [0.000, 0.000, 0.707, 0.707]' in out
    assert out.count('TF_DENORMALIZED_QUATERNION') == 1, out


def _check_pdf(data: bytes) -> bytes:
    """A PDF whose cross-reference table points at its objects; its page's drawing, inflated."""
    import re
    import zlib
    assert data.startswith(b'%PDF-') and data.rstrip().endswith(b'%%EOF')
    xref = int(re.search(rb'startxref\n(\d+)\n', data).group(1))
    assert data[xref:xref + 4] == b'xref'
    count = int(re.match(rb'xref\n0 (\d+)\n', data[xref:]).group(1))
    table = data[xref:].split(b'\n')[3:3 + count - 1]
    for number, row in enumerate(table, start=1):
        offset = int(row[:10])
        assert data[offset:].startswith(f'{number} 0 obj'.encode()), (number, offset)
    stream = re.search(rb'stream\n(.*)\nendstream', data, re.S).group(1)
    return zlib.decompress(stream)


def test_view_frames_names_its_files_as_ros_does(domain, tmp_path):
    """`ros2 run tf2_tools view_frames` as the course types it, in the current directory:
    frames_YYYY-MM-DD_HH.MM.SS.gv and .pdf (here with no tf data: the PDF says so)."""
    import re
    import shutil
    import subprocess
    import sys
    done = subprocess.run([sys.executable, '-m', 'zros.cli.main', 'run', 'tf2_tools', 'view_frames', '-t', '0.3'],
                          cwd=tmp_path, capture_output=True, text=True, timeout=30)
    assert done.returncode == 0, done.stderr
    names = sorted(p.name for p in tmp_path.iterdir())
    assert len(names) == 2 and all(re.fullmatch(r'frames_\d{4}-\d\d-\d\d_\d\d\.\d\d\.\d\d\.(gv|pdf)', n) for n in names)
    assert names[0][:-3] == names[1][:-4], names
    pdf = tmp_path / names[1]
    assert b'(No tf data received)' in _check_pdf(pdf.read_bytes())
    if shutil.which('pdftoppm'):   # poppler, where installed, reads it too
        subprocess.run(['pdftoppm', '-png', '-r', '20', str(pdf), str(tmp_path / 'page')], check=True, timeout=30)
        assert (tmp_path / 'page-1.png').read_bytes().startswith(b'\x89PNG')


def test_view_frames_writes_every_frame(spawn, zros_cli, tmp_path):
    spawn.script(TURTLE_BROADCASTER, name='broadcaster').wait_for_output('broadcasting', timeout=20)
    result = zros_cli('run', 'tf2_tools', 'view_frames', '-t', '1.5', '-o', str(tmp_path / 'frames'), timeout=30)
    assert result.returncode == 0, result
    dot = (tmp_path / 'frames.gv').read_text()
    for edge in ('"world" -> "turtle1"', '"turtle1" -> "carrot1"', '"sea" -> "island"'):
        assert edge in dot, dot
    assert 'Average rate: ' in dot and 'view_frames Result' in dot
    drawing = _check_pdf((tmp_path / 'frames.pdf').read_bytes())
    for text in (b'(world)', b'(turtle1)', b'(carrot1)', b'(sea)', b'(island)', b'(view_frames Result)'):
        assert text in drawing, text
    tree = zros_cli('tf', 'tree', '-t', '1.5')
    assert tree.returncode == 0, tree
    lines = tree.stdout.splitlines()
    assert 'world' in lines and 'sea' in lines and '└── island (static)' in lines, tree.stdout
    assert any(line.startswith('└── turtle1 (') and line.endswith(' Hz)') for line in lines), tree.stdout
    assert '    └── carrot1 (static)' in lines, tree.stdout
    import json
    monitor = {row['frame']: row for row in json.loads(zros_cli('tf', 'monitor', '-t', '1.5', '--json').stdout)}
    assert monitor['turtle1']['parent'] == 'world' and monitor['turtle1']['rate_hz'] > 5
    assert monitor['carrot1']['static'] is True
