"""nav2_map_server's tools as real processes: map_server (a lifecycle node serving /map
transient local, GetMap and load_map, keeping its map when a load fails), map_saver_server and
map_saver_cli (writing what /map carries, byte for byte the file map_server read)."""
from __future__ import annotations

import signal
import threading

import numpy as np

from conftest import assert_clean_failure, wait_until
from zros.map_io import OccupancyMap, save_map


def _maps(tmp_path):
    rng = np.random.default_rng(7)
    first = OccupancyMap(rng.choice(np.array([-1, 0, 100], dtype=np.int8), size=(20, 30)), 0.05, (-1.0, -0.5, 0.0))
    second = OccupancyMap(rng.choice(np.array([-1, 0, 100], dtype=np.int8), size=(12, 16)), 0.1, (2.0, 3.0, 0.0))
    return save_map(first, tmp_path / 'first'), save_map(second, tmp_path / 'second')


def test_map_server_lifecycle_load_map_and_map_savers(spawn, make_context, tmp_path, zros_cli):
    from zros.executors import SingleThreadedExecutor
    from zros.lifecycle import LifecycleClient
    from zros.node import Node
    from zros.qos import DurabilityPolicy, QoSProfile
    from interfaces.nav2_msgs.srv import LoadMap, SaveMap
    from interfaces.nav_msgs.msg import OccupancyGrid
    from interfaces.nav_msgs.srv import GetMap
    (first_yaml, first_pgm), (second_yaml, second_pgm) = _maps(tmp_path)
    server = spawn.node('nav2_map_server', 'map_server', '--ros-args', '-p', f'yaml_filename:={first_yaml}')

    node = Node('probe', context=make_context())
    executor = SingleThreadedExecutor(context=node.context)
    executor.add_node(node)
    threading.Thread(target=executor.spin, daemon=True).start()
    lifecycle = LifecycleClient(node, 'map_server')
    assert lifecycle.wait_for_services(timeout_sec=15), server.output()
    assert lifecycle.get_state().label == 'unconfigured'
    assert lifecycle.change_state('configure', timeout_sec=10) and lifecycle.change_state('activate', timeout_sec=10)

    maps = []
    node.create_subscription(OccupancyGrid, 'map', maps.append,
                             QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL))
    wait_until(lambda: maps, 10, message='/map from map_server (transient local, subscribed late)')
    assert (maps[0].info.width, maps[0].info.height, maps[0].header.frame_id) == (30, 20, 'map')

    load = node.create_client(LoadMap, 'map_server/load_map')
    get = node.create_client(GetMap, 'map_server/map')
    assert load.wait_for_service(timeout_sec=10) and get.wait_for_service(timeout_sec=10)
    (tmp_path / 'broken.yaml').write_text('image: first.pgm\nresolution: 0.05\norigin: [0, 0]\n'
                                          'occupied_thresh: 0.65\nfree_thresh: 0.2\n')
    failed = load.call(LoadMap.Request(map_url=str(tmp_path / 'broken.yaml')), timeout_sec=10)
    assert failed.result == LoadMap.Response.RESULT_INVALID_MAP_METADATA
    missing = load.call(LoadMap.Request(map_url=f'file://{tmp_path}/none.yaml'), timeout_sec=10)
    assert missing.result == LoadMap.Response.RESULT_MAP_DOES_NOT_EXIST
    assert get.call(GetMap.Request(), timeout_sec=10).map.info.width == 30          # the old map stays
    server.wait_for_output('origin: must have 3 elements', timeout=5)

    loaded = load.call(LoadMap.Request(map_url=f'file://{second_yaml}'), timeout_sec=10)
    assert loaded.result == LoadMap.Response.RESULT_SUCCESS and loaded.map.info.width == 16
    wait_until(lambda: maps[-1].info.width == 16, 10, message='the new map on /map')

    saver = spawn.node('nav2_map_server', 'map_saver_server', '--ros-args', '-p', 'autostart:=true')
    save = node.create_client(SaveMap, 'map_saver/save_map')
    assert save.wait_for_service(timeout_sec=15), saver.output()
    assert save.call(SaveMap.Request(map_url=str(tmp_path / 'served'), map_topic='map'), timeout_sec=15).result
    assert (tmp_path / 'served.pgm').read_bytes() == second_pgm.read_bytes()
    failed = save.call(SaveMap.Request(map_url=str(tmp_path / 'bad'), map_mode='fancy'), timeout_sec=15)
    assert not failed.result and not (tmp_path / 'bad.yaml').exists()

    saved = zros_cli('run', 'nav2_map_server', 'map_saver_cli', '-f', tmp_path / 'saved', timeout=30)
    assert saved.returncode == 0, saved
    assert (tmp_path / 'saved.pgm').read_bytes() == second_pgm.read_bytes()
    assert (tmp_path / 'saved.yaml').read_text() == second_yaml.read_text().replace('second.pgm', 'saved.pgm')

    executor.shutdown(timeout_sec=1)
    server.signal(signal.SIGINT)
    assert server.wait(5) == 0


def test_map_server_autostart_with_a_bad_file_fails_in_one_line(tmp_path, zros_cli, domain):
    (tmp_path / 'bad.yaml').write_text('image: nothing.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n'
                                       'occupied_thresh: 0.65\nfree_thresh: 0.2\nmode: fancy\n')
    result = zros_cli('run', 'nav2_map_server', 'map_server', '--ros-args', '-p', f'yaml_filename:={tmp_path}/bad.yaml',
                      '-p', 'autostart:=true', timeout=30)
    assert_clean_failure(result, 'bad.yaml', "mode: unsupported 'fancy'")


def test_map_saver_cli_bad_arguments_and_no_map(tmp_path, zros_cli, domain):
    assert_clean_failure(zros_cli('run', 'nav2_map_server', 'map_saver_cli', '-f', tmp_path / 'm', '--mode', 'fancy'),
                         "unsupported map mode 'fancy'")
    assert_clean_failure(zros_cli('run', 'nav2_map_server', 'map_saver_cli', '--occ', 'high'), "--occ: not a number")
    result = zros_cli('run', 'nav2_map_server', 'map_saver_cli', '-f', tmp_path / 'm', '--ros-args', '-p',
                      'save_map_timeout:=0.5', timeout=30)
    assert result.returncode == 1 and "no map on '/map' within 0.5 s" in result.stderr + result.stdout, result
    assert not (tmp_path / 'm.pgm').exists()
