"""roslib (npm, run by node) through `zros run rosbridge_server rosbridge_websocket`, as a web UI
uses it: it subscribes /chatter from the demo talker, calls the demo /add_two_ints, publishes
/cmd_vel that moves the simulated TurtleBot3, and sends a navigate_to_pose goal that succeeds.
One stack for the module (turtlebot3_world, TurtleBot3's navigation2.launch.py, the demo nodes,
the bridge); the client is nothing but the npm packages roslib and ws."""
from __future__ import annotations

import json
import math
import os
import re
import sys
import threading
from pathlib import Path
from typing import Any

import pytest

from conftest import REPO, run_cli, wait_until
from npm_roslib import roslib_modules, run_node

PORT_LINE = re.compile(r'Rosbridge WebSocket server started on port (\d+)')

# Each client prints one JSON line per thing it saw and exits 0 when it has seen what it wanted.
CHATTER = '''
import { Ros, Topic } from 'ROSLIB';
const ros = new Ros({ url: process.argv[2] });
const chatter = new Topic({ ros, name: '/chatter', messageType: 'std_msgs/msg/String', compression: process.argv[3] });
const seen = [];
chatter.subscribe((message) => {
  seen.push(message.data);
  if (seen.length === 2) { console.log(JSON.stringify(seen)); chatter.unsubscribe(); ros.close(); }
});
'''

ADD_TWO_INTS = '''
import { Ros, Service } from 'ROSLIB';
const ros = new Ros({ url: process.argv[2] });
const service = new Service({ ros, name: '/add_two_ints', serviceType: 'example_interfaces/srv/AddTwoInts' });
service.callService({ a: 19, b: 23 }, (response) => { console.log(JSON.stringify(response)); ros.close(); },
                    (error) => { console.error('call failed: ' + error); process.exit(1); });
'''

# Drive forward for 2 s at 0.15 m/s and report /odom's position before and after.
CMD_VEL = '''
import { Ros, Topic } from 'ROSLIB';
const ros = new Ros({ url: process.argv[2] });
const odom = new Topic({ ros, name: '/odom', messageType: 'nav_msgs/msg/Odometry', throttle_rate: 100 });
const cmdVel = new Topic({ ros, name: '/cmd_vel', messageType: 'geometry_msgs/msg/Twist' });
let start = null, last = null;
odom.subscribe((message) => {
  last = message.pose.pose.position;
  if (start === null) {
    start = last;
    const drive = setInterval(() => cmdVel.publish({ linear: { x: 0.15 } }), 100);
    setTimeout(() => {
      clearInterval(drive);
      cmdVel.publish({});
      setTimeout(() => { console.log(JSON.stringify({ start, end: last })); ros.close(); }, 500);
    }, 2000);
  }
});
'''

# The robot's initial pose to AMCL, then a goal; prints the feedback count and the result's status.
NAVIGATE = '''
import { Ros, Topic, Action } from 'ROSLIB';
const ros = new Ros({ url: process.argv[2] });
const initialPose = new Topic({ ros, name: '/initialpose',
                                messageType: 'geometry_msgs/msg/PoseWithCovarianceStamped' });
const pose = { position: { x: -2.0, y: -0.5, z: 0.0 }, orientation: { x: 0, y: 0, z: 0, w: 1 } };
const covariance = Array(36).fill(0); covariance[0] = covariance[7] = 0.25; covariance[35] = 0.07;
initialPose.publish({ header: { frame_id: 'map' }, pose: { pose, covariance } });
const navigate = new Action({ ros, name: '/navigate_to_pose', actionType: 'nav2_msgs/action/NavigateToPose' });
let feedback = 0;
setTimeout(() => navigate.sendGoal(
  { pose: { header: { frame_id: 'map' }, pose: { position: { x: 0.5, y: 0.5 }, orientation: { w: 1 } } } },
  (result) => { console.log(JSON.stringify({ status: 'succeeded', feedback, result })); ros.close(); },
  (message) => { feedback += 1; },
  (error) => { console.log(JSON.stringify({ status: 'failed', error, feedback })); ros.close(); }), 3000);
'''


@pytest.fixture(scope='module')
def bridge_url(module_spawn: Any) -> str:
    roslib_modules()   # skip before the stack starts when there is no roslib
    module_spawn.command(sys.executable, '-m', 'zros', 'launch', 'turtlebot3_gazebo', 'turtlebot3_world.launch.yaml',
                         'real_time_factor:=3.0', name='world')
    module_spawn.command(sys.executable, '-m', 'zros', 'launch', 'turtlebot3_navigation2', 'navigation2.launch.py',
                         'use_sim_time:=True', 'rviz:=false', name='navigation2')
    module_spawn.node('demo_nodes_py', 'talker')
    module_spawn.node('demo_nodes_py', 'add_two_ints_server')
    bridge = module_spawn.node('rosbridge_server', 'rosbridge_websocket', '--ros-args', '-p', 'port:=0',
                               '-p', 'address:=127.0.0.1', '-p', 'use_sim_time:=true')
    output = bridge.wait_for_output('Rosbridge WebSocket server started on port', timeout=30)
    return f'ws://127.0.0.1:{PORT_LINE.search(output).group(1)}'


def _client(script: str, url: str, *args: str, timeout: float = 60.0) -> Any:
    result = run_node(script, url, *args, timeout=timeout)
    assert result.returncode == 0 and result.stdout.strip(), result
    return json.loads(result.stdout.strip().splitlines()[-1])


@pytest.mark.parametrize('compression', ['none', 'cbor'])
def test_roslib_subscribes_chatter(bridge_url: str, compression: str) -> None:
    seen = _client(CHATTER, bridge_url, compression)
    assert len(seen) == 2 and all(text.startswith('Hello World: ') for text in seen)


def test_roslib_calls_add_two_ints(bridge_url: str) -> None:
    assert _client(ADD_TWO_INTS, bridge_url) == {'sum': 42}


def test_roslib_navigate_to_pose_goal_succeeds(bridge_url: str) -> None:
    wait_until(lambda: run_cli('lifecycle', 'get', '/bt_navigator', timeout=30).stdout.startswith('active'), 180,
               message='bt_navigator active')
    outcome = _client(NAVIGATE, bridge_url, timeout=240)
    assert outcome['status'] == 'succeeded', outcome
    assert outcome['feedback'] > 0 and 'result' in outcome


@pytest.fixture
def example_page(tmp_path: Path) -> str:
    """examples/roslib_turtlebot.html served on loopback beside the npm install's node_modules."""
    from http.server import SimpleHTTPRequestHandler, ThreadingHTTPServer
    (tmp_path / 'roslib_turtlebot.html').symlink_to(REPO / 'examples' / 'roslib_turtlebot.html')
    (tmp_path / 'node_modules').symlink_to(roslib_modules())

    class Handler(SimpleHTTPRequestHandler):
        extensions_map = {**SimpleHTTPRequestHandler.extensions_map, '.mjs': 'text/javascript',
                          '.js': 'text/javascript'}

        def __init__(self, *args: Any, **kwargs: Any) -> None:
            super().__init__(*args, directory=str(tmp_path), **kwargs)

        def log_message(self, *args: Any) -> None:
            pass
    server = ThreadingHTTPServer(('127.0.0.1', 0), Handler)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    yield f'http://127.0.0.1:{server.server_address[1]}/roslib_turtlebot.html'
    server.shutdown()
    server.server_close()


def test_example_page_shows_the_pose_and_its_button_reaches_a_goal(bridge_url: str, example_page: str,
                                                                   tmp_path: Path) -> None:
    """The example page in headless Chromium; ZROS_DOC_IMAGES=1 also writes docs/images/roslib_page.png."""
    from zros.view.headless import Browser, find_chromium
    if find_chromium() is None:
        pytest.skip('chromium is needed for the example page (apt-get install chromium)')
    with Browser(width=760, height=420) as browser:
        browser.open(f'{example_page}?url={bridge_url}', wait_for='document.getElementById("source")')
        browser.wait_for('document.getElementById("source").textContent === "/amcl_pose"', timeout=30)
        browser.evaluate('document.getElementById("goal-x").value = "-2.0";'
                         'document.getElementById("goal-y").value = "-0.5"')
        browser.click_text('Send navigate_to_pose goal')
        browser.wait_for('document.getElementById("goal-status").textContent.includes("distance remaining")', 60)
        browser.wait_for('parseFloat(document.getElementById("x").textContent) < -0.8', 120)   # half way
        if os.environ.get('ZROS_DOC_IMAGES'):
            browser.save_screenshot(REPO / 'docs' / 'images' / 'roslib_page.png')
        browser.wait_for('document.getElementById("goal-status").textContent.includes("succeeded")', 180)
        browser.save_screenshot(tmp_path / 'done.png')
        x = float(browser.evaluate('document.getElementById("x").textContent'))
        y = float(browser.evaluate('document.getElementById("y").textContent'))
    assert math.hypot(x + 2.0, y + 0.5) < 0.5, (x, y)


def test_roslib_cmd_vel_moves_the_robot(bridge_url: str) -> None:
    moved = _client(CMD_VEL, bridge_url)
    start, end = moved['start'], moved['end']
    assert math.hypot(end['x'] - start['x'], end['y'] - start['y']) > 0.1, moved
