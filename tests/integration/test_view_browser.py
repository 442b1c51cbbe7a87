"""The scene view in a real headless Chromium, against real nodes: the map, the scan and the robot
are drawn where TF puts them (checked on screenshot pixels), the Pose Estimate and Nav2 Goal
tools publish what a click-drag means, and a missing transform says so in the page.

One world for the module: fake_robot standing still at (-1.6, -0.5) heading 0.5 rad, with the odom
frame 0.5 m from the map origin (so ignoring TF would misplace everything), robot_state_publisher
with the TurtleBot3 burger URDF, and a SceneView seen from straight above.
"""
from __future__ import annotations

import math
import os
import queue
import threading
import time
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from conftest import REPO, background_node, wait_until
from zros.view.headless import Browser, find_chromium

pytestmark = pytest.mark.skipif(find_chromium() is None, reason='Debian chromium is not installed (.ci/run '
                                'installs it where apt-get is available)')

ROBOT = (-1.6, -0.5, 0.5)         # x [m], y [m], yaw [rad] of base_footprint in the map
ODOM_OFFSET = 0.5                 # map -> odom along x [m]
DISTANCE = 9.0                    # [m] camera height above the map centre
WINDOW = (1600, 820)
SHOTS = Path(os.environ['ZROS_VIEW_SHOTS']) if os.environ.get('ZROS_VIEW_SHOTS') else None   # to look at them


class World:
    """The view, its node and the browser, for the module's tests."""

    def __init__(self, view: Any, node: Any, browser: Browser) -> None:
        self.view, self.node, self.browser = view, node, browser
        self.rect: dict[str, float] = {}
        self.scale = 0.0

    def top_down(self) -> None:
        """Look straight down at the map origin and learn the pixel scale from the camera's fov."""
        def settled() -> Any:
            clients = list(self.view.server.get_clients().values())
            if clients and abs(clients[0].camera.position[2] - DISTANCE) < 0.05:
                return clients[0].camera
            self.view.set_camera('top-down', focal=(0.0, 0.0, 0.0), distance=DISTANCE)
            return None
        camera = wait_until(settled, 30, interval=0.5, message='the browser camera to move above the map')
        from zros.view.scene.app import PANEL_WIDTHS
        height = self.browser.evaluate('document.querySelector("canvas").getBoundingClientRect().height')
        left, right = PANEL_WIDTHS          # viser centres the camera between the docked panels
        self.rect = {'x': left, 'y': 0.0, 'w': WINDOW[0] - left - right, 'h': height}
        self.scale = (self.rect['h'] / 2) / math.tan(camera.fov / 2) / DISTANCE   # px per metre on the ground

    def pixel(self, x: float, y: float) -> tuple[float, float]:
        """Where ground point (x, y) of the fixed frame appears in the page [CSS px]."""
        return (self.rect['x'] + self.rect['w'] / 2 + x * self.scale,
                self.rect['y'] + self.rect['h'] / 2 - y * self.scale)

    def colour(self, pixels: np.ndarray, x: float, y: float) -> np.ndarray:
        px, py = self.pixel(x, y)
        return pixels[int(round(py)), int(round(px))].astype(int)


@pytest.fixture(scope='module')
def world(module_domain, module_spawn, tmp_path_factory):
    from zros.view.scene.app import SceneView
    from zros.view.scene.config import DisplayConfig, GridConfig, ViewConfig
    x, y, yaw = ROBOT
    module_spawn.node('zros_view', 'fake_robot', '--ros-args', '-p', 'speed:=0.0', '-p', f'x:={x}', '-p', f'y:={y}',
                      '-p', f'yaw:={yaw}', '-p', f'map_to_odom_x:={ODOM_OFFSET}', '-p', 'particles:=10')
    urdf = (REPO / 'nodes' / 'turtlebot3_description' / 'urdf' / 'turtlebot3_burger.urdf').read_text()
    module_spawn.node('robot_state_publisher', 'robot_state_publisher', '--ros-args', '-p',
                      f'robot_description:={urdf}')
    config = ViewConfig(fixed_frame='map', grid=GridConfig(enabled=False),
                        camera={'mode': 'top-down', 'distance': DISTANCE}, displays=[
        DisplayConfig('Map', 'Map', '/map', options={'alpha': 1.0}),
        DisplayConfig('LaserScan', 'LaserScan', '/scan', options={'color': (255, 0, 0), 'size': 0.06}),
        DisplayConfig('RobotModel', 'RobotModel', '/robot_description'),
        DisplayConfig('LaserScan', 'Ghost scan', '/ghost_scan')])
    with background_node('browser_test') as node, SceneView(node, config=config, port=0) as view, \
            Browser(width=WINDOW[0], height=WINDOW[1]) as browser:
        browser.open(view.url, wait_for='document.querySelector("canvas")', timeout=60)
        browser.evaluate('document.querySelectorAll(".mantine-Notification-closeButton").forEach(b => b.click())')
        result = World(view, node, browser)
        result.top_down()
        yield result


def _save(world: World, tmp_path: Path, name: str) -> np.ndarray:
    return world.browser.save_screenshot(SHOTS / name if SHOTS else tmp_path / name)


def test_map_scan_and_robot_are_drawn_where_tf_puts_them(world, tmp_path):
    from nodes.zros_view.fake_robot import SCAN_X, cast_scan, world_grid
    x, y, yaw = ROBOT
    sx, sy = x + SCAN_X * math.cos(yaw), y + SCAN_X * math.sin(yaw)
    ranges = cast_scan(world_grid(), sx, sy, yaw)
    angles = yaw + np.arange(ranges.size) * (2 * math.pi / ranges.size)
    hits = [(sx + r * math.cos(a), sy + r * math.sin(a)) for r, a in zip(ranges, angles) if np.isfinite(r)]

    def red(pixel: np.ndarray) -> bool:
        return pixel[0] > 180 and pixel[1] < 90 and pixel[2] < 90

    shot: dict[str, Any] = {}

    def drawn() -> bool:
        pixels = shot['pixels'] = _save(world, tmp_path, 'scene.png')
        shot['found'] = sum(any(red(world.colour(pixels, hx + dx, hy + dy)) for dx in (-0.03, 0, 0.03)
                                for dy in (-0.03, 0, 0.03)) for hx, hy in hits)
        return shot['found'] >= 0.8 * len(hits)
    assert world.browser.until(drawn, timeout=40), \
        f'{shot["found"]} of {len(hits)} scan points where TF puts them (scale {world.scale:.1f} px/m, canvas ' \
        f'{world.rect}; screenshot {tmp_path / "scene.png"})'
    pixels = shot['pixels']
    # The map: a pillar is black, free space white, beyond the walls unknown grey-green.
    assert world.colour(pixels, 1.1, 1.1).max() < 70, 'pillar at (1.1, 1.1)'
    assert world.colour(pixels, 0.55, 1.65).min() > 225, 'free space at (0.55, 1.65)'
    assert np.abs(world.colour(pixels, 3.6, 3.2) - (112, 137, 134)).max() < 25, 'unknown space at (3.6, 3.2)'
    # No scan point where there is no wall: the middle of the free space between pillars.
    assert not red(world.colour(pixels, 0.55, -0.55))
    # The robot model (burger: grey base plate, dark lidar on top) sits at base_footprint's place.
    robot = world.colour(pixels, x, y)
    assert robot.max() < 200 and not red(robot), f'no robot drawn at {x, y}: {robot}'
    assert world.colour(pixels, x - ODOM_OFFSET, y).min() > 200, 'a robot drawn at its odom pose, as if map = odom'


def _drag_tool(world: World, button: str, start: tuple[float, float], end: tuple[float, float],
               msg_type: Any, topic: str) -> Any:
    inbox: queue.SimpleQueue = queue.SimpleQueue()
    subscription = world.node.create_subscription(msg_type, topic, inbox.put, 10)
    try:
        wait_until(lambda: world.node.count_publishers(topic) >= 1, 10, message=f'the view publishing {topic}')
        world.browser.click_text(button)
        wait_until(lambda: world.view.tool is not None, 10, message=f'{button} armed')
        time.sleep(0.5)                                  # the pick surface reaches the page
        world.browser.drag(world.pixel(*start), world.pixel(*end), steps=15, step_delay=0.05)
        return inbox.get(timeout=15)
    finally:
        world.node.destroy_subscription(subscription)


def test_pose_estimate_tool_publishes_initialpose(world):
    from interfaces.geometry_msgs.msg import PoseWithCovarianceStamped
    msg = _drag_tool(world, '2D Pose Estimate', (1.0, 0.5), (1.0, 1.5), PoseWithCovarianceStamped, '/initialpose')
    p, q = msg.pose.pose.position, msg.pose.pose.orientation
    assert msg.header.frame_id == 'map'
    assert (p.x, p.y) == pytest.approx((1.0, 0.5), abs=0.1)
    assert math.atan2(2 * (q.w * q.z + q.x * q.y), 1 - 2 * (q.y * q.y + q.z * q.z)) == \
        pytest.approx(math.pi / 2, abs=0.15)
    covariance = np.asarray(msg.pose.covariance).reshape(6, 6)
    assert (covariance[0, 0], covariance[1, 1]) == (0.25, 0.25)
    assert covariance[5, 5] == pytest.approx((math.pi / 12) ** 2)
    world.browser.wait_for('document.querySelector("[data-tool-hint]").innerText.includes("Published /initialpose")')


def test_nav2_goal_tool_publishes_goal_pose(world):
    from interfaces.geometry_msgs.msg import PoseStamped
    msg = _drag_tool(world, 'Nav2 Goal', (-0.5, 1.6), (-1.5, 1.6), PoseStamped, '/goal_pose')
    p, q = msg.pose.position, msg.pose.orientation
    assert msg.header.frame_id == 'map'
    assert (p.x, p.y) == pytest.approx((-0.5, 1.6), abs=0.1)
    assert abs(math.remainder(2 * math.atan2(q.z, q.w) - math.pi, 2 * math.pi)) < 0.15


def test_missing_transform_is_shown_in_the_page(world):
    from interfaces.sensor_msgs.msg import LaserScan
    publisher = world.node.create_publisher(LaserScan, '/ghost_scan', 10)
    stop = threading.Event()

    def publish() -> None:
        while not stop.wait(0.2):
            scan = LaserScan(angle_increment=0.1, range_min=0.1, range_max=5.0, ranges=[1.0] * 10)
            scan.header.frame_id = 'ghost_frame'
            scan.header.stamp = world.node.get_clock().now().to_msg()
            publisher.publish(scan)
    thread = threading.Thread(target=publish, daemon=True)
    thread.start()
    try:
        expected = 'No transform from [ghost_frame] to [map]'
        ghost = next(d for d in world.view.displays if d.name == 'Ghost scan')
        wait_until(lambda: expected in ghost.status.text, 30, message=lambda: f'the status, now {ghost.status}')
        text = world.browser.wait_for(
            f'[...document.querySelectorAll("[data-status=error]")].map(e => e.innerText)'
            f'.find(t => t.includes({expected!r}))', timeout=30)
        assert 'does not exist' in text
    finally:
        stop.set()
        thread.join(timeout=2)


def test_particle_cloud_and_path_are_drawn_where_they_are(world, tmp_path):
    """AMCL's nav2_msgs/ParticleCloud and a planner's Path, published here, added as a user adds them."""
    from interfaces.geometry_msgs.msg import Pose, PoseStamped
    from interfaces.nav2_msgs.msg import Particle, ParticleCloud
    from interfaces.nav_msgs.msg import Path as PathMsg
    from zros.view.scene.config import DisplayConfig
    from zros.node import Node
    publisher = Node('planner_and_amcl', context=world.node.context)    # the view ignores its own node's topics
    cloud_pub = publisher.create_publisher(ParticleCloud, '/nav2_particle_cloud', 10)
    path_pub = publisher.create_publisher(PathMsg, '/test_plan', 10)
    cloud = ParticleCloud(particles=[Particle(pose=Pose(), weight=0.02) for _ in range(50)])
    cloud.header.frame_id = 'map'
    for i, particle in enumerate(cloud.particles):      # a ring of 0.12 m round (0.55, -0.55), heading out
        a = i * 2 * math.pi / 50
        particle.pose.position.x, particle.pose.position.y = 0.55 + 0.12 * math.cos(a), -0.55 + 0.12 * math.sin(a)
        particle.pose.orientation.z, particle.pose.orientation.w = math.sin(a / 2), math.cos(a / 2)
    path = PathMsg()
    path.header.frame_id = 'map'
    for i in range(11):                                   # along y = -1.65, from x = -0.5 to 0.5
        pose = PoseStamped()
        pose.header.frame_id = 'map'
        pose.pose.position.x, pose.pose.position.y = -0.5 + 0.1 * i, -1.65
        pose.pose.orientation.w = 1.0
        path.poses.append(pose)
    stop = threading.Event()

    def publish() -> None:                                # as AMCL and the planner do: again and again
        while not stop.wait(0.2):
            cloud_pub.publish(cloud)
            path_pub.publish(path)
    thread = threading.Thread(target=publish, daemon=True)
    thread.start()
    # As a .rviz file's PoseArray display says: geometry_msgs/PoseArray; the view follows what is published.
    particles = world.view.add_display(DisplayConfig('PoseArray', 'Particles', '/nav2_particle_cloud',
                                                     'geometry_msgs/msg/PoseArray', options={'color': (0, 200, 0)}))
    plan = world.view.add_display(DisplayConfig('Path', 'Plan', '/test_plan', 'nav_msgs/msg/Path',
                                                options={'color': (255, 0, 255), 'width': 5.0}))
    try:
        wait_until(lambda: particles.status.text.startswith('50 poses in [map]'), 30,
                   message=lambda: f'the particles, status {particles.status}')
        wait_until(lambda: plan.status.text.startswith('11 poses in [map]'), 30,
                   message=lambda: f'the plan, status {plan.status}')

        def magenta(p: np.ndarray) -> bool:
            return p[0] > 180 and p[2] > 180 and p[1] < 110

        def green_around(pixels: np.ndarray, x: float, y: float, radius: float) -> int:
            cx, cy = world.pixel(x, y)
            r = int(radius * world.scale)
            patch = pixels[int(cy) - r:int(cy) + r, int(cx) - r:int(cx) + r].astype(int)
            return int(((patch[..., 1] > 140) & (patch[..., 1] > patch[..., 0] + 50)
                        & (patch[..., 1] > patch[..., 2] + 50)).sum())

        def drawn() -> bool:
            pixels = _save(world, tmp_path, 'particles_and_plan.png')
            line = sum(any(magenta(world.colour(pixels, x, -1.65 + dy)) for dy in (-0.02, 0, 0.02))
                       for x in np.linspace(-0.4, 0.4, 9))
            return (green_around(pixels, 0.55, -0.55, 0.45) >= 40 and line >= 8
                    and green_around(pixels, -0.55, 0.55, 0.45) == 0)
        assert world.browser.until(drawn, timeout=30), f'particles and plan not where they are ({tmp_path})'
    finally:
        stop.set()
        thread.join(timeout=2)
        world.view.remove_display(particles)
        world.view.remove_display(plan)
        publisher.destroy_node()


def test_teleop_pad_publishes_cmd_vel(world):
    from interfaces.geometry_msgs.msg import Twist
    inbox: queue.SimpleQueue = queue.SimpleQueue()
    subscription = world.node.create_subscription(Twist, '/cmd_vel', inbox.put, 10)
    try:
        world.browser.click_text('Teleop (/cmd_vel)', selector='p, span, div, button')
        world.browser.click_text('▲ Forward')
        twist = inbox.get(timeout=15)
        assert (twist.linear.x, twist.angular.z) == (pytest.approx(0.2), 0.0)
        assert inbox.get(timeout=5).linear.x == pytest.approx(0.2)      # repeated until Stop
        world.browser.click_text('■ Stop')
        deadline = time.monotonic() + 15
        while inbox.get(timeout=max(0.1, deadline - time.monotonic())).linear.x != 0.0:
            pass
    finally:
        world.node.destroy_subscription(subscription)


def test_graph_and_console_pages(world, tmp_path):
    world.browser.click_text('Graph')
    shown = '[...document.querySelectorAll("[data-graph] [data-vertex]")].map(g => g.dataset.vertex)'
    vertices = world.browser.wait_for(f'(() => {{ const v = {shown}; return v.includes("n:/fake_robot") '
                                      '&& v.includes("t:/scan") && v; })()', timeout=20)
    assert 't:/tf' not in vertices and 't:/rosout' not in vertices       # rqt_graph's default hides
    # Left to right: /fake_robot publishes /scan, which the view's node subscribes to.
    left = '(v => document.querySelector(`[data-graph] [data-vertex="${v}"]`).getBoundingClientRect().x)'
    assert world.browser.evaluate(f'{left}("n:/fake_robot") < {left}("t:/scan") '
                                  f'&& {left}("t:/scan") < {left}("n:/browser_test")')
    world.browser.toggle('tf')                                          # show tf: /tf and /tf_static appear
    world.browser.wait_for(f'(() => {{ const v = {shown}; return v.includes("t:/tf") && v.includes("t:/tf_static"); }})()',
                           timeout=20)
    _save(world, tmp_path, 'graph_page.png')
    world.browser.toggle('tf')
    world.browser.wait_for(f'!{shown}.includes("t:/tf")', timeout=20)
    world.browser.click_text('Console')
    world.node.get_logger().warn('the console shows this line')
    world.browser.wait_for('document.body.innerText.includes("the console shows this line")', timeout=20)
    assert 'WARN' in world.browser.evaluate('document.body.innerText')
