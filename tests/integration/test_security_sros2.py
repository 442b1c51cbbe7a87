"""SROS2's words in zros: `zros security create_keystore/create_enclave/list_enclaves`, and
ROS_SECURITY_KEYSTORE / ROS_SECURITY_ENABLE / ROS_SECURITY_STRATEGY honoured, the enclave from
`--ros-args --enclave`: a talker and a listener talk through the keystore's mTLS router, and a
listener whose certificate comes from another keystore hears nothing."""
from __future__ import annotations

import os
import sys
import time

from conftest import HUB_BASE_PORT, assert_clean_failure

CLI = ['-m', 'zros.cli.main']


def test_sros2_steps_secure_talker_and_listener(domain, spawn, tmp_path, zros_cli, monkeypatch):
    keys, rogue = tmp_path / 'demo_keystore', tmp_path / 'rogue_keystore'
    made = zros_cli('security', 'create_keystore', str(keys))
    assert made.returncode == 0 and 'router enclave' in made.stdout, made
    for name in ('/talker_listener/talker', '/talker_listener/listener'):
        assert zros_cli('security', 'create_enclave', str(keys), name).returncode == 0
    listed = zros_cli('security', 'list_enclaves', str(keys)).stdout.split()
    assert listed == ['/router', '/talker_listener/listener', '/talker_listener/talker'], listed
    assert zros_cli('security', 'create_keystore', str(rogue)).returncode == 0
    assert zros_cli('security', 'create_enclave', str(rogue), '/talker_listener/listener').returncode == 0
    assert_clean_failure(zros_cli('security', 'create_enclave', str(tmp_path / 'none'), '/x'), 'not a keystore')
    assert_clean_failure(zros_cli('security', 'create_enclave', str(keys), '/bad name'), 'not usable')

    port = HUB_BASE_PORT + domain   # this test's reserved port; only loopback
    monkeypatch.setenv('ROS_SECURITY_KEYSTORE', str(keys))
    monkeypatch.setenv('ROS_SECURITY_ENABLE', 'true')
    monkeypatch.setenv('ROS_SECURITY_STRATEGY', 'Enforce')
    monkeypatch.setenv('ZROS_CONNECT', f'tls/localhost:{port}')
    router = spawn(*_zros(), 'router', '--listen', f'tls/127.0.0.1:{port}', name='router')
    router.wait_for_output(f'listening on tls/127.0.0.1:{port}', timeout=15)
    spawn.node('demo_nodes', 'talker', '--ros-args', '--enclave', '/talker_listener/talker')
    listener = spawn.node('demo_nodes', 'listener', '--ros-args', '--enclave', '/talker_listener/listener')
    listener.wait_for_output('I heard: [Hello World:', timeout=20)
    # without ZROS_CONNECT, a node finding the keystore's router on the hub port is its client
    monkeypatch.delenv('ZROS_CONNECT')
    spawn.node('demo_nodes', 'listener', '--ros-args', '--enclave', '/talker_listener/listener',
               '-r', '__node:=hub_listener').wait_for_output('I heard: [Hello World:', timeout=20)
    monkeypatch.setenv('ZROS_CONNECT', f'tls/localhost:{port}')

    monkeypatch.setenv('ROS_SECURITY_KEYSTORE', str(rogue))   # right name, wrong CA
    outsider = spawn.node('demo_nodes', 'listener', '--ros-args', '--enclave', '/talker_listener/listener')
    time.sleep(3.0)
    assert 'I heard' not in outsider.output(), outsider.output()

    monkeypatch.setenv('ROS_SECURITY_KEYSTORE', str(keys))
    assert_clean_failure(zros_cli('topic', 'list'), 'no enclave given')           # Enforce, no enclave
    missing = zros_cli('node', 'list', env={**os.environ, 'ROS_SECURITY_ENCLAVE_OVERRIDE': '/nobody'})
    assert_clean_failure(missing, "no enclave '/nobody'")
    monkeypatch.setenv('ROS_SECURITY_STRATEGY', 'Permissive')
    monkeypatch.delenv('ZROS_CONNECT')
    permissive = zros_cli('topic', 'list')   # warns, then runs without security (its own loopback hub)
    assert permissive.returncode == 0 and 'running without security' in permissive.stderr, permissive


def test_sros2_tutorial_as_printed_needs_no_router(domain, spawn, tmp_path, zros_cli, monkeypatch):
    """The sros2 tutorial: create_keystore, create_enclave, the three variables, then a talker
    and a listener in two terminals, nothing else. They link over mutual TLS on loopback; a
    process without security, or with another keystore's certificate, hears nothing."""
    keys, rogue = tmp_path / 'demo_keystore', tmp_path / 'rogue_keystore'
    assert zros_cli('security', 'create_keystore', str(keys)).returncode == 0
    for name in ('/talker_listener/talker', '/talker_listener/listener'):
        assert zros_cli('security', 'create_enclave', str(keys), name).returncode == 0
    assert zros_cli('security', 'create_keystore', str(rogue)).returncode == 0
    assert zros_cli('security', 'create_enclave', str(rogue), '/talker_listener/listener').returncode == 0
    monkeypatch.setenv('ROS_SECURITY_KEYSTORE', str(keys))
    monkeypatch.setenv('ROS_SECURITY_ENABLE', 'true')
    monkeypatch.setenv('ROS_SECURITY_STRATEGY', 'Enforce')
    talker = spawn.node('demo_nodes_cpp', 'talker', '--ros-args', '--enclave', '/talker_listener/talker')
    listener = spawn.node('demo_nodes_cpp', 'listener', '--ros-args', '--enclave', '/talker_listener/listener')
    listener.wait_for_output('I heard: [Hello World:', timeout=20)
    assert 'cannot reach' not in talker.output() + listener.output()
    from zros.config import settings_from_env
    assert settings_from_env(enclave='/talker_listener/talker').hub_endpoint.startswith('tls/127.0.0.1:')

    monkeypatch.setenv('ROS_SECURITY_KEYSTORE', str(rogue))   # right name, wrong CA
    outsider = spawn.node('demo_nodes_cpp', 'listener', '--ros-args', '--enclave', '/talker_listener/listener')
    monkeypatch.delenv('ROS_SECURITY_ENABLE')                 # no security at all
    plain = spawn.node('demo_nodes_cpp', 'listener')
    listener.wait_for_output('I heard: [Hello World: 5]', timeout=20)   # a few more messages went by
    time.sleep(2.0)
    assert 'I heard' not in outsider.output() + plain.output(), outsider.output() + plain.output()


def test_a_secure_node_waiting_for_its_router_says_what_to_do(domain, tmp_path, zros_cli, monkeypatch):
    keys = tmp_path / 'demo_keystore'
    assert zros_cli('security', 'create_keystore', str(keys)).returncode == 0
    assert zros_cli('security', 'create_enclave', str(keys), '/cli').returncode == 0
    monkeypatch.setenv('ROS_SECURITY_KEYSTORE', str(keys))
    monkeypatch.setenv('ROS_SECURITY_ENABLE', 'true')
    monkeypatch.setenv('ROS_SECURITY_ENCLAVE_OVERRIDE', '/cli')
    monkeypatch.setenv('ZROS_CONNECT', f'tls/localhost:{HUB_BASE_PORT + domain}')   # nothing listens there
    result = zros_cli('topic', 'list')
    assert "cannot reach tls/localhost" in result.stderr and 'start it there (`zros router`' in result.stderr, result
    assert 'leave ZROS_CONNECT and ZROS_DISCOVERY unset' in result.stderr, result


def _zros():
    return [sys.executable, *CLI]
