"""Bags and the ROS 2 ecosystem: default (CDR) recordings that rosbags and mcap_ros2 read with their
own type definitions, `zros bag convert` both ways, rosbag2 bags (MCAP and .db3) written by
rosbags played into zros, and corrupt or truncated files refused in one line."""
from __future__ import annotations

import array
import glob

import msgpack
import numpy as np
import pytest
from rosbags.rosbag2 import Reader, StoragePlugin, Writer
from rosbags.typesys import Stores, get_typestore

from conftest import assert_clean_failure
from integration.test_bag import PUBLISHER, echo_child, wait_lines, write_bag
from zros.node import Node

# ROS 2's own hash of std_msgs/msg/String (ros2cli's test_cli.py expects the same).
STRING_RIHS01 = 'RIHS01_df668c740482bbd48fb39d76a70dfd4bd59db1288021743503259e948f6b1a18'
JAZZY = get_typestore(Stores.ROS2_JAZZY)   # rosbags' own copy of the ROS 2 definitions, not zros's


def rosbags_messages(bag):
    """[(topic, type, decoded message)] and {topic: connection} through rosbags' reader."""
    with Reader(bag) as reader:
        connections = {c.topic: c for c in reader.connections}
        return [(c.topic, c.msgtype, JAZZY.deserialize_cdr(data, c.msgtype))
                for c, _, data in reader.messages()], connections


def test_a_recording_with_defaults_is_read_by_rosbags_and_mcap_ros2(domain, spawn, tmp_path, zros_cli):
    from mcap.reader import make_reader
    from mcap_ros2.decoder import DecoderFactory
    source = spawn.script(PUBLISHER, name='source')
    source.wait_for_output('ready', timeout=15)
    bag = tmp_path / 'cdr'
    result = zros_cli('bag', 'record', '-a', '-o', str(bag), '--max-duration', '1.5', timeout=30)
    assert result.returncode == 0, result
    source.kill()

    messages, connections = rosbags_messages(bag)
    strings = [int(m.data[1:]) for topic, _, m in messages if topic == '/bagged']
    frames = [int(m.header.frame_id[1:]) for topic, _, m in messages if topic == '/posed']
    assert len(strings) >= 50 and strings == list(range(strings[0], strings[0] + len(strings)))
    assert frames == list(range(frames[0], frames[0] + len(frames)))
    bagged = connections['/bagged']
    assert bagged.ext.serialization_format == 'cdr' and bagged.digest == STRING_RIHS01
    assert bagged.ext.offered_qos_profiles[0].reliability.name == 'RELIABLE'
    assert connections['/posed'].msgtype == 'geometry_msgs/msg/PoseStamped'

    with open(glob.glob(str(bag / '*.mcap'))[0], 'rb') as stream:
        reader = make_reader(stream, decoder_factories=[DecoderFactory()])
        decoded = [(channel.topic, msg) for _, channel, _, msg in reader.iter_decoded_messages(log_time_order=True)]
    assert [int(msg.data[1:]) for topic, msg in decoded if topic == '/bagged'] == strings
    assert [msg.pose.orientation.w for topic, msg in decoded if topic == '/posed'][:1] == [1.0]

    info = zros_cli('bag', 'info', str(bag))
    assert info.returncode == 0 and 'Serialization Format: cdr' in info.stdout, info


def test_convert_both_ways_keeps_values(tmp_path, zros_cli):
    from zros.bag.writer import BagWriter
    from zros.message import deserialize, serialize
    from interfaces.sensor_msgs.msg import LaserScan
    write_bag(tmp_path / 'native', [10, 20, 30])
    scans = tmp_path / 'scans'
    # the codec may hand out lists, numpy arrays or array.array: every one must convert
    with BagWriter(scans) as writer:
        writer.add_topic('/scan', LaserScan._TYPE, type_hash=LaserScan._HASH, qos='B:V:L5')
        for i, ranges in enumerate(([1.0, 2.0], np.array([3.0, 4.5], np.float32), array.array('f', [5.0]))):
            scan = LaserScan(ranges=ranges, angle_max=1.5)
            scan.header.frame_id = 'base_scan'
            writer.write('/scan', serialize(scan), log_time=1_000 + i)

    for storage in ('mcap', 'sqlite3'):
        out = tmp_path / f'as_cdr_{storage}'
        result = zros_cli('bag', 'convert', str(tmp_path / 'native'), str(out), '--format', 'cdr', '-s', storage)
        assert result.returncode == 0 and 'Converted 8 messages' in result.stdout, result
        messages, connections = rosbags_messages(out)
        assert [m.data for topic, _, m in messages if topic == '/played'] == ['p0', 'p1', 'p2', 'p3']
        assert connections['/played'].digest == STRING_RIHS01
        back = tmp_path / f'back_{storage}'
        assert zros_cli('bag', 'convert', str(out), str(back), '-f', 'msgpack').returncode == 0
        _, recorded = zros_bag_messages(back)
        assert [msgpack.unpackb(d)[0] for t, d in recorded if t == '/played'] == ['p0', 'p1', 'p2', 'p3']

    assert zros_cli('bag', 'convert', str(scans), str(tmp_path / 'scans_cdr'), '-f', 'cdr').returncode == 0
    messages, connections = rosbags_messages(tmp_path / 'scans_cdr')
    assert [m.ranges.tolist() for _, _, m in messages] == [[1.0, 2.0], [3.0, 4.5], [5.0]]
    assert connections['/scan'].ext.offered_qos_profiles[0].reliability.name == 'BEST_EFFORT'
    assert zros_cli('bag', 'convert', str(tmp_path / 'scans_cdr'), str(tmp_path / 'scans_back'),
                    '-f', 'msgpack').returncode == 0
    _, recorded = zros_bag_messages(tmp_path / 'scans_back')
    decoded = [deserialize(data, LaserScan) for _, data in recorded]
    assert [list(s.ranges) for s in decoded] == [[1.0, 2.0], [3.0, 4.5], [5.0]]
    assert {s.header.frame_id for s in decoded} == {'base_scan'} and decoded[0].angle_max == 1.5

    assert_clean_failure(zros_cli('bag', 'convert', str(scans), str(tmp_path / 'native'), '-f', 'cdr'),
                         'already exists')
    assert_clean_failure(zros_cli('bag', 'convert', str(scans), str(tmp_path / 'x'), '-f', 'msgpack',
                                  '-s', 'sqlite3'), 'sqlite3')


def zros_bag_messages(bag):
    from zros.bag.reader import open_bag
    reader = open_bag(bag)
    return reader.summary(), [(m.topic, m.data) for m in reader.messages()]


def write_foreign_bag(path, storage):
    """A rosbag2 bag written by rosbags alone (its own ROS 2 definitions and CDR codec)."""
    String, Twist = JAZZY.types['std_msgs/msg/String'], JAZZY.types['geometry_msgs/msg/Twist']
    Vector3 = JAZZY.types['geometry_msgs/msg/Vector3']
    t = 1_700_000_000_000_000_000
    with Writer(path, version=9, storage_plugin=storage) as writer:
        chatter = writer.add_connection('/chatter', 'std_msgs/msg/String', typestore=JAZZY)
        cmd = writer.add_connection('/cmd_vel', 'geometry_msgs/msg/Twist', typestore=JAZZY)
        for i in range(6):
            t += 50_000_000
            writer.write(chatter, t, JAZZY.serialize_cdr(String(data=f'robot {i}'), 'std_msgs/msg/String'))
            twist = Twist(linear=Vector3(x=0.1 * i, y=0.0, z=0.0), angular=Vector3(x=0.0, y=0.0, z=-0.5))
            writer.write(cmd, t + 1, JAZZY.serialize_cdr(twist, 'geometry_msgs/msg/Twist'))


@pytest.mark.parametrize('storage', [StoragePlugin.MCAP, StoragePlugin.SQLITE3], ids=['mcap', 'db3'])
def test_play_a_rosbag2_bag_into_zros(context, spawn, tmp_path, zros_cli, storage):
    bag = tmp_path / 'from_robot'
    write_foreign_bag(bag, storage)
    info = zros_cli('bag', 'info', str(bag))
    assert info.returncode == 0, info
    assert 'Storage id:        ' + ('mcap' if storage == StoragePlugin.MCAP else 'sqlite3') in info.stdout
    assert 'Messages:          12' in info.stdout and 'Serialization Format: cdr' in info.stdout, info
    probe = Node('bag_probe', context=context)
    chatter = echo_child(spawn, probe, '/chatter', 'std_msgs/msg/String')
    cmd = echo_child(spawn, probe, '/cmd_vel', 'geometry_msgs/msg/Twist')
    target = bag if storage == StoragePlugin.MCAP else next(bag.glob('*.db3'))  # a directory or a bare .db3
    result = zros_cli('bag', 'play', str(target), timeout=30)
    assert result.returncode == 0 and 'Traceback' not in result.stderr, result
    assert wait_lines(chatter, 6) == [f'robot {i}' for i in range(6)]
    rows = [[float(v) for v in line.split(',')] for line in wait_lines(cmd, 6)]
    assert [round(r[0], 6) for r in rows] == [round(0.1 * i, 6) for i in range(6)]
    assert {r[5] for r in rows} == {-0.5}


def test_corrupt_and_truncated_bags_fail_in_one_line(tmp_path, zros_cli):
    write_bag(tmp_path / 'good', [10] * 20)
    data = next((tmp_path / 'good').glob('*.mcap')).read_bytes()
    for name, content in (('header_only', data[:8]), ('cut', data[:300]), ('garbage', data[:8] + b'\x07' * 500)):
        (tmp_path / f'{name}.mcap').write_bytes(content)
        for verb in ('info', 'play'):
            assert_clean_failure(zros_cli('bag', verb, str(tmp_path / f'{name}.mcap')), 'corrupt')
    flipped = bytearray(data)
    for i in range(120, 400):
        flipped[i] ^= 0x5A   # inside the first (compressed) chunk; the summary at the end is intact
    (tmp_path / 'flipped.mcap').write_bytes(bytes(flipped))
    assert_clean_failure(zros_cli('bag', 'play', str(tmp_path / 'flipped.mcap')), 'corrupt')
    (tmp_path / 'broken.db3').write_bytes(b'SQLite format 3\x00' + b'\x00' * 200)
    assert_clean_failure(zros_cli('bag', 'info', str(tmp_path / 'broken.db3')), 'broken.db3')
