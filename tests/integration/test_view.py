"""The web view and `zros image save`: Image conversion, the HTTP endpoints, the
CLI verbs, and a headless Chromium that loads the page and shows turtlesim's trail."""
from __future__ import annotations

import json
import os
import shutil
import subprocess
import threading
import urllib.request
from typing import Any

import numpy as np
import pytest

from conftest import wait_until
from zros.view.image import UnsupportedEncoding, image_to_array
from zros.image_io import decode_image

BACKGROUND = (69, 86, 255)


# -- pixels ------------------------------------------------------------------------------------
def _image(encoding: str, pixels: np.ndarray, *, step: int | None = None, bigendian: int = 0) -> Any:
    from interfaces.sensor_msgs.msg import Image
    height, width = pixels.shape[:2]
    row = pixels.reshape(height, -1).view(np.uint8)
    step = step or row.shape[1]
    padded = np.zeros((height, step), dtype=np.uint8)
    padded[:, :row.shape[1]] = row
    return Image(height=height, width=width, encoding=encoding, is_bigendian=bigendian, step=step,
                 data=padded.reshape(-1))


def test_image_to_array_encodings():
    rgb = np.arange(4 * 3 * 3, dtype=np.uint8).reshape(4, 3, 3)
    assert (image_to_array(_image('rgb8', rgb)) == rgb).all()
    assert (image_to_array(_image('bgr8', rgb[..., ::-1].copy())) == rgb).all()
    assert (image_to_array(_image('rgb8', rgb, step=16)) == rgb).all()     # padded rows
    rgba = np.dstack([rgb, np.full((4, 3), 200, dtype=np.uint8)])
    assert (image_to_array(_image('bgra8', rgba[..., [2, 1, 0, 3]].copy())) == rgba).all()
    mono16 = (np.arange(12, dtype=np.uint16).reshape(4, 3) * 5000)
    assert (image_to_array(_image('mono16', mono16)) == (mono16 >> 8)).all()
    assert (image_to_array(_image('mono16', mono16.astype('>u2'), bigendian=1)) == (mono16 >> 8)).all()
    depth = np.linspace(1.0, 3.0, 12, dtype=np.float32).reshape(4, 3)
    scaled = image_to_array(_image('32FC1', depth))
    assert scaled.min() == 0 and scaled.max() == 255
    with pytest.raises(UnsupportedEncoding, match="cannot show encoding 'yuv422'"):
        image_to_array(_image('yuv422', rgb))
    short = _image('rgb8', rgb)
    short.height = 40
    with pytest.raises(UnsupportedEncoding, match='too short'):
        image_to_array(short)


# -- the server over zros -----------------------------------------------------------------------
class Spinner:
    def __init__(self, executor: Any) -> None:
        self.executor = executor
        self.thread = threading.Thread(target=self._run, daemon=True)
        self.thread.start()

    def _run(self) -> None:
        try:
            self.executor.spin()
        except Exception:  # noqa: BLE001 - ends with the context
            pass

    def close(self) -> None:
        self.executor.shutdown(timeout_sec=2)
        self.thread.join(timeout=5)


def _gradient(seq: int) -> np.ndarray:
    ys, xs = np.mgrid[0:30, 0:40]
    return np.dstack([xs * 6, ys * 8, np.full_like(xs, seq % 256)]).astype(np.uint8)


@pytest.fixture
def camera(context):
    """A node publishing a 40 x 30 rgb8 image on /camera/image every 50 ms (blue = frame count)."""
    from interfaces.sensor_msgs.msg import Image
    from zros.executors import SingleThreadedExecutor
    from zros.node import Node
    from zros.qos import qos_profile_sensor_data
    node = Node('camera', context=context)
    pub = node.create_publisher(Image, '/camera/image', qos_profile_sensor_data)
    count = [0]

    def tick() -> None:
        count[0] += 1
        pub.publish(Image(height=30, width=40, encoding='rgb8', step=120, data=_gradient(count[0]).reshape(-1)))
    node.create_timer(0.05, tick)
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(node)
    spinner = Spinner(executor)
    yield node
    spinner.close()


@pytest.fixture
def view(make_context):
    """A ViewServer on a free port, with its own context and node, spun in the background."""
    from zros.executors import SingleThreadedExecutor
    from zros.node import Node
    from zros.view.server import ViewServer
    ctx = make_context()
    node = Node('view_test', context=ctx)
    server = ViewServer(node, port=0, idle_timeout=30.0).start()
    executor = SingleThreadedExecutor(context=ctx)
    executor.add_node(node)
    spinner = Spinner(executor)
    yield server
    server.close()
    spinner.close()


def _get(url: str, timeout: float = 10.0) -> tuple[int, dict[str, str], bytes]:
    try:
        with urllib.request.urlopen(url, timeout=timeout) as response:
            return response.status, dict(response.headers), response.read()
    except urllib.error.HTTPError as exc:
        return exc.code, dict(exc.headers), exc.read()


def test_view_lists_topics_and_serves_frames(camera, view):
    def listed() -> Any:
        status, _, body = _get(view.url + 'api/topics')
        data = json.loads(body)
        return status == 200 and {'name': '/camera/image', 'type': 'sensor_msgs/msg/Image'} in data['topics'] and data
    data = wait_until(listed, 10, message='/camera/image in /api/topics')
    assert data['default'] == '/camera/image'

    status, headers, body = _get(view.url + 'frame.png?topic=/camera/image&timeout=5')
    assert status == 200 and headers['Content-Type'] == 'image/png'
    assert (headers['X-Frame-Width'], headers['X-Frame-Height'], headers['X-Frame-Encoding']) == ('40', '30', 'rgb8')
    pixels = decode_image(body)
    assert pixels.shape == (30, 40, 3)
    assert (pixels[..., :2] == _gradient(0)[..., :2]).all()
    seq = int(headers['X-Frame-Seq'])
    # Long poll: the next request waits for a newer frame.
    status, headers, _ = _get(view.url + f'frame.png?topic=/camera/image&after={seq}&timeout=5')
    assert status == 200 and int(headers['X-Frame-Seq']) > seq

    # The page, with the first frame as the image's own source; its script and style.
    status, headers, page = _get(view.url + '?topic=/camera/image')
    assert status == 200 and b'src="frame.png?topic=/camera/image&amp;timeout=3"' in page
    assert b'data-initial-topic="&quot;/camera/image&quot;"' in page
    for name, kind in (('app.js', 'text/javascript'), ('style.css', 'text/css')):
        status, headers, _ = _get(view.url + 'static/' + name)
        assert status == 200 and headers['Content-Type'].startswith(kind)
    assert _get(view.url + 'static/../server.py')[0] == 404
    assert _get(view.url + 'frame.png?topic=/bad%20name&timeout=0')[0] == 400
    assert _get(view.url + 'frame.png?topic=/nothing/here&timeout=0.2')[0] == 204

    # The multipart stream (for <img src=stream>) starts with a PNG part.
    with urllib.request.urlopen(view.url + 'stream?topic=/camera/image', timeout=10) as response:
        assert response.headers['Content-Type'].startswith('multipart/x-mixed-replace')
        head = response.read(64)
    assert head.startswith(b'--zrosframe\r\nContent-Type: image/png\r\n')


def test_image_save_cli(camera, zros_cli, tmp_path):
    out = tmp_path / 'frame.png'
    result = zros_cli('image', 'save', '/camera/image', str(out), '--timeout', '10')
    assert result.returncode == 0, result
    assert 'Saved a 40x30 rgb8 frame of /camera/image to' in result.stdout
    pixels = decode_image(out.read_bytes())
    assert (pixels[..., :2] == _gradient(0)[..., :2]).all()
    missing = zros_cli('image', 'save', '/no/such/image', str(tmp_path / 'x.png'), '--timeout', '0.5')
    assert missing.returncode == 1 and "no image arrived on '/no/such/image' within 0.5 s" in missing.stderr


def test_view_cli_prints_its_urls(camera, spawn):
    import sys
    child = spawn(sys.executable, '-m', 'zros.cli.main', 'view', '--port', '0', '--topic', '/camera/image', name='view')
    text = child.wait_for_output('full-size images at', 20)
    scene = text.split('serving ', 1)[1].split(' ', 1)[0]
    assert scene.startswith('http://127.0.0.1:') and '(Ctrl-C to stop)' in text
    status, _, page = _get(scene)
    assert status == 200 and b'<html' in page.lower()                  # viser's client, shipped in its wheel
    images = text.split('full-size images at ', 1)[1].split()[0]
    assert images.startswith('http://127.0.0.1:') and images.endswith('/?topic=/camera/image')
    status, _, body = _get(images.split('?')[0] + 'frame.png?topic=/camera/image&timeout=5')
    assert status == 200 and decode_image(body).shape == (30, 40, 3)


def test_view_cli_bad_config_and_busy_port(zros_cli, tmp_path):
    import socket

    from conftest import assert_clean_failure
    bad = tmp_path / 'bad.rviz'
    bad.write_text('a: [')
    assert_clean_failure(zros_cli('view', '-d', str(bad), '--port', '0'), 'is not valid YAML')
    assert_clean_failure(zros_cli('view', '-d', str(tmp_path / 'none.rviz'), '--port', '0'), 'cannot read')
    with socket.socket() as busy:
        busy.bind(('127.0.0.1', 0))
        busy.listen()
        port = busy.getsockname()[1]
        assert_clean_failure(zros_cli('view', '--port', str(port)), 'address already in use', '--port')


# -- a real browser ------------------------------------------------------------------------------
def _chromium() -> str | None:
    for name in ('chromium', 'chromium-browser'):
        path = shutil.which(name)
        if path:
            return path
    return '/usr/bin/chromium' if os.path.exists('/usr/bin/chromium') else None


def test_browser_shows_the_turtlesim_trail(spawn, view, tmp_path):
    browser = _chromium()
    if browser is None:
        pytest.skip('Debian chromium is not installed (.ci/run installs it with apt-get where apt is '
                    'available): the headless-browser test cannot run here')
    from interfaces.turtlesim.srv import SetPen, TeleportAbsolute
    sim = spawn.node('turtlesim', 'turtlesim_node')
    sim.wait_for_output('Spawning turtle [turtle1]', 20)
    node = view.node
    for srv_type, name, request in (
            (SetPen, '/turtle1/set_pen', SetPen.Request(r=255, g=0, b=0, width=8, off=0)),
            (TeleportAbsolute, '/turtle1/teleport_absolute', TeleportAbsolute.Request(x=2.0, y=2.0, theta=0.0))):
        client = node.create_client(srv_type, name)
        assert client.wait_for_service(timeout_sec=10)
        client.call(request, timeout_sec=5)
    wait_until(lambda: '/turtlesim/image' in view.store.image_topics(), 10, message='/turtlesim/image')
    shot = tmp_path / 'view.png'
    argv = [browser, '--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
            '--disable-background-networking', '--disable-component-update', '--disable-sync',
            '--hide-scrollbars', '--window-size=560,620', f'--user-data-dir={tmp_path / "profile"}',
            f'--screenshot={shot}', view.page_url('/turtlesim/image')]
    result = subprocess.run(argv, capture_output=True, timeout=90, cwd=tmp_path)
    assert shot.exists(), f'no screenshot; chromium said:\n{result.stderr.decode(errors="replace")[-2000:]}'
    pixels = decode_image(shot.read_bytes())[..., :3].astype(int)
    # The canvas is where the background colour is; the trail from the middle (5.54, 5.54) to
    # (2, 2) crosses (3.77, 3.77), at canvas pixel (170, 329).
    background = (np.abs(pixels - BACKGROUND).sum(axis=2) <= 6)
    rows, cols = np.nonzero(background)
    assert rows.size > 100_000, 'the canvas is not on the page'
    top, left = rows.min(), cols.min()
    assert (rows.max() - top + 1, cols.max() - left + 1) == (500, 500)
    trail = pixels[top + 329, left + 170]
    assert np.abs(trail - (255, 0, 0)).sum() <= 12, f'expected the red trail, found {trail}'
    assert not background[top + 329, left + 170]


def test_a_fixed_frame_alone_still_shows_every_topic(context):
    """A launch file that starts the view with `fixed_frame: odom` and no config file: every
    topic must still be added as it appears (not TF alone), and the frame stays odom."""
    from zros.view.scene.node import ViewNode
    node = ViewNode('view', fixed_frame='odom', port=0, context=context)
    try:
        assert node.view.auto and node.view.ctx.fixed_frame == 'odom'
        assert not node.view._fixed_auto                 # TF's map appearing later does not move it
    finally:
        node.destroy_node()


def _static_transform(broadcaster: Any, parent: str, child: str, x: float) -> None:
    from interfaces.geometry_msgs.msg import TransformStamped
    transform = TransformStamped()
    transform.header.frame_id, transform.child_frame_id = parent, child
    transform.transform.translation.x = x
    transform.transform.rotation.w = 1.0
    broadcaster.sendTransform(transform)


def test_fixed_frame_moves_to_map_when_it_appears_unless_someone_chose(domain):
    """The view starts before SLAM: odom first, then map as soon as TF has it (the dropdown's
    own on_update, run by viser for the view's assignments too, must not count as a choice);
    a frame picked by hand stays."""
    from conftest import background_node
    from zros.tf2_ros import StaticTransformBroadcaster
    from zros.view.scene.app import SceneView
    with background_node('robot_tf') as robot, background_node('view_frames') as node, \
            SceneView(node, port=0) as view:
        static = StaticTransformBroadcaster(robot)
        _static_transform(static, 'odom', 'base_footprint', 0.5)
        # the dropdown follows the view's frame on the view's own thread: wait for both
        wait_until(lambda: view.ctx.fixed_frame == 'odom' and view.fixed_frame_input.value == 'odom', 20,
                   message='the fixed frame odom (no map yet)')
        _static_transform(static, 'map', 'odom', 1.0)             # SLAM starts: map appears
        wait_until(lambda: view.ctx.fixed_frame == 'map' and view.fixed_frame_input.value == 'map', 20,
                   message='the fixed frame to move to map')
        assert view._fixed_auto
        view.set_fixed_frame('odom', user=True)                  # someone picks odom
        view._slow_step(0.0)                                      # what the slow loop does, twice
        view._slow_step(0.0)
        assert view.ctx.fixed_frame == 'odom' and view.fixed_frame_input.value == 'odom'


def test_screenshot_waits_for_the_map(spawn, zros_cli, tmp_path):
    """`zros view --screenshot` saves the page once its displays are drawn: the map's texture
    is decoded after the message that says `N x M cells`, so the shot must wait for it."""
    from zros.view.headless import find_chromium
    from zros.view.scene.config import DisplayConfig, GridConfig, ViewConfig, dump_view
    from zros.view.scene.convert import UNKNOWN_RGB
    if find_chromium() is None:
        pytest.skip('Debian chromium is not installed (.ci/run installs it where apt-get is available)')
    spawn.node('zros_view', 'fake_robot', '--ros-args', '-p', 'speed:=0.0')
    config = tmp_path / 'map.view.yaml'
    config.write_text(dump_view(ViewConfig(fixed_frame='map', grid=GridConfig(enabled=False),
                                           camera={'mode': 'top-down', 'distance': 9.0},
                                           displays=[DisplayConfig('Map', 'Map', '/map', options={'alpha': 1.0})])))
    shot = tmp_path / 'shot.png'
    result = zros_cli('view', '-d', str(config), '--port', '0', '--screenshot', str(shot), '--timeout', '40',
                      timeout=120)
    assert result.returncode == 0 and f'wrote {shot}' in result.stdout, result.stdout + result.stderr
    assert 'not every display was drawn' not in result.stderr
    pixels = decode_image(shot.read_bytes())[..., :3].astype(int)
    unknown = (np.abs(pixels - UNKNOWN_RGB).max(axis=2) <= 12).sum()       # the grey-green round the room
    walls = (pixels.max(axis=2) <= 40).sum()                                # black walls and pillars
    assert unknown > 20_000 and walls > 2_000, f'no map in {shot}: {unknown} unknown, {walls} wall pixels'


def test_ctrl_c_stops_the_view_within_launchs_grace(spawn, tmp_path):
    """Under `zros launch`, Ctrl-C (SIGINT) ends the view with a page open before the launch's
    sigterm_timeout: viser's stop waits for an idle connection Chromium opened at page load."""
    import signal
    import sys

    from zros.view.headless import Browser, find_chromium
    if find_chromium() is None:
        pytest.skip('Debian chromium is not installed (.ci/run installs it where apt-get is available)')
    launch = tmp_path / 'view.launch.yaml'
    launch.write_text('launch:\n- node: {pkg: zros_view, exec: view, name: view, output: screen,\n'
                      '          param: [{name: port, value: 0}]}\n')
    child = spawn.command(sys.executable, '-m', 'zros', 'launch', str(launch), name='launch')
    url = child.wait_for_output('Serving the view on', 60).split('Serving the view on ', 1)[1].split()[0]
    with Browser(width=1000, height=700) as browser:
        browser.open(url, wait_for='document.querySelector("canvas")', timeout=60)
        browser.wait_for('!!document.querySelector("[data-status]")', timeout=30)   # the page talks to the view
        child.popen.send_signal(signal.SIGINT)
        assert child.wait(timeout=30) == 0, child.output()[-3000:]
    output = child.output()
    assert 'failed to terminate' not in output and 'process has finished cleanly' in output, output[-3000:]
