"""zros.testing, as a user's test sees it: the plugin's fixtures and the wait helpers, against
real node processes."""
from __future__ import annotations

import os

import pytest

from interfaces.example_interfaces.srv import AddTwoInts
from interfaces.std_msgs.msg import String
from zros.testing import WaitTimeout, call_service, wait_for_message, wait_for_node, wait_for_topic


def test_fixtures_give_a_private_domain_and_clean_processes(zros_domain, zros_processes, zros_node):
    assert os.environ['ZROS_DOMAIN_ID'] == str(zros_domain)
    talker = zros_processes.run('demo_nodes', 'talker')
    server = zros_processes.run('demo_nodes', 'add_two_ints_server')
    probe = zros_node('probe')
    wait_for_node(probe, '/talker', timeout=20.0)
    wait_for_topic(probe, '/chatter', publishers=1, timeout=10.0)
    assert wait_for_message(probe, String, '/chatter', timeout=10.0).data.startswith('Hello World: ')
    assert call_service(probe, AddTwoInts, '/add_two_ints', AddTwoInts.Request(a=2, b=3), timeout=10.0).sum == 5
    assert talker.stop() is not None and talker.popen.poll() is not None
    assert 'Publishing' in talker.output()
    assert server.popen.poll() is None          # still up; the fixture stops it after the test


def test_waits_say_what_they_waited_for(zros_node):
    probe = zros_node('probe')
    with pytest.raises(WaitTimeout, match="timed out after 0.3 s waiting for a message on '/nothing'"):
        wait_for_message(probe, String, '/nothing', timeout=0.3)
    with pytest.raises(WaitTimeout, match="waiting for the node '/nobody'"):
        wait_for_node(probe, '/nobody', timeout=0.3)
    with pytest.raises(WaitTimeout, match="waiting for the service '/none'"):
        call_service(probe, AddTwoInts, '/none', AddTwoInts.Request(), timeout=0.3)
