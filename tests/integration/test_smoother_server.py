"""nav2_smoother: SimpleSmoother as plain code (straighter paths, ends kept, obstacles respected,
cusps kept), then the smoother_server process answering `smooth_path` and BasicNavigator's
smoothPath."""
from __future__ import annotations

import numpy as np
import pytest

from conftest import activate
from zros.navigation.costmap import LETHAL_OBSTACLE
from zros.navigation.path_smoother import (SimpleSmootherParams, approximate_yaws, directional_segments,
                                           smooth_path)


def _zigzag(n: int = 40, amplitude: float = 0.015) -> np.ndarray:
    x = np.linspace(0.0, 2.0, n)
    return np.stack([x, amplitude * (-1.0) ** np.arange(n)], axis=1)


def _turning(points: np.ndarray) -> float:
    """Total heading change along a path [rad]: what smoothing reduces."""
    d = np.diff(points, axis=0)
    return float(np.abs(np.diff(np.unwrap(np.arctan2(d[:, 1], d[:, 0])))).sum())


def test_smoothing_reduces_turning_and_keeps_the_ends():
    path = _zigzag()
    out = smooth_path(path, np.zeros(len(path)), SimpleSmootherParams())
    assert out.completed
    assert _turning(out.points) < 0.2 * _turning(path)
    assert out.points[0] == pytest.approx(path[0]) and out.points[-1] == pytest.approx(path[-1])
    assert np.abs(out.yaws[1:-1]).max() < 0.3                    # headings recomputed along x
    assert path[1, 1] == pytest.approx(-0.015)                   # the input is not modified


def test_an_obstacle_stops_smoothing_at_the_last_admissible_path():
    # A path bending around a block inside its corner: smoothing would cut the corner through it.
    path = np.concatenate([np.stack([np.linspace(0, 1, 20), np.zeros(20)], 1),
                           np.stack([np.ones(20), np.linspace(0.05, 1, 20)], 1)])

    def cost_at(xy: np.ndarray) -> np.ndarray:
        inside = (xy[:, 0] > 0.85) & (xy[:, 0] < 0.99) & (xy[:, 1] > 0.01) & (xy[:, 1] < 0.15)
        return np.where(inside, LETHAL_OBSTACLE, 0).astype(np.uint8)

    free = smooth_path(path, np.zeros(len(path)), SimpleSmootherParams())
    assert cost_at(free.points).max() == LETHAL_OBSTACLE         # unchecked, it cuts through the block
    checked = smooth_path(path, np.zeros(len(path)), SimpleSmootherParams(), cost_at=cost_at)
    assert not checked.completed
    assert cost_at(checked.points).max() == 0
    assert _turning(checked.points) <= _turning(path)


def test_limits_cusps_and_short_paths():
    path = _zigzag()
    assert not smooth_path(path, np.zeros(len(path)), SimpleSmootherParams(max_its=3)).completed
    assert not smooth_path(path, np.zeros(len(path)), SimpleSmootherParams(), max_time=0.0).completed
    short = _zigzag(8)
    assert smooth_path(short, np.zeros(8), SimpleSmootherParams()).points == pytest.approx(short)
    forward = np.stack([np.linspace(0, 1, 15), np.zeros(15)], 1)
    there_and_back = np.concatenate([forward, forward[-2::-1] + [0.0, 0.01]])
    assert directional_segments(there_and_back) == [(0, 14), (14, 28)]
    out = smooth_path(there_and_back, np.zeros(len(there_and_back)), SimpleSmootherParams())
    assert out.points[14] == pytest.approx(there_and_back[14])   # the cusp stays
    backwards = approximate_yaws(forward[::-1], np.zeros(15))     # driven backwards: heading 0, moving -x
    assert backwards[:-1] == pytest.approx(np.zeros(14), abs=1e-9)


def _costmap_msg(stamp) -> object:
    """A 3 x 3 m free costmap in `map` with a lethal block at x 1.2..1.6, y 0.5..0.9."""
    from interfaces.nav2_msgs.msg import Costmap
    grid = np.zeros((60, 60), np.uint8)
    grid[10:18, 24:32] = LETHAL_OBSTACLE
    msg = Costmap()
    msg.header.frame_id = 'map'
    msg.header.stamp = stamp
    msg.metadata.resolution = 0.05
    msg.metadata.size_x, msg.metadata.size_y = 60, 60
    msg.data = grid.ravel()
    return msg


NAVIGATOR = '''
import numpy as np
import zros
from zros.nav2_simple_commander.robot_navigator import BasicNavigator
from zros.navigation.node_support import path_msg

zros.init()
navigator = BasicNavigator()
stamp = navigator.get_clock().now().to_msg()
x = np.linspace(0.2, 2.2, 40)
zigzag = np.stack([x, 0.2 + 0.015 * (-1.0) ** np.arange(40)], axis=1)
smoothed = navigator.smoothPath(path_msg(zigzag, np.zeros(40), 'map', stamp))
print('smoothed:', smoothed.header.frame_id, [[p.pose.position.x, p.pose.position.y] for p in smoothed.poses],
      flush=True)
through = np.stack([np.linspace(0.2, 2.5, 30), np.full(30, 0.7)], 1)
print('through the block:', navigator.smoothPath(path_msg(through, np.zeros(30), 'map', stamp),
                                                 check_for_collision=True), flush=True)
print('error code:', navigator.result_future.result().result.error_code, flush=True)
print('unknown id:', navigator.smoothPath(path_msg(zigzag, np.zeros(40), 'map', stamp), smoother_id='nope'),
      navigator.result_future.result().result.error_code, flush=True)
'''


def test_smoother_server_and_basic_navigator(spawn, probe):
    import ast

    from zros.qos import DurabilityPolicy, QoSProfile
    from interfaces.nav2_msgs.action import SmoothPath
    from interfaces.nav2_msgs.msg import Costmap
    from interfaces.nav_msgs.msg import Path
    server = spawn.node('nav2_smoother', 'smoother_server')
    activate(probe, 'smoother_server', server)
    costmap_pub = probe.create_publisher(Costmap, 'global_costmap/costmap_raw',
                                         QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL))
    costmap_pub.publish(_costmap_msg(probe.get_clock().now().to_msg()))
    published: list = []
    probe.create_subscription(Path, 'plan_smoothed', published.append, 1)

    script = spawn.script(NAVIGATOR, name='navigator')
    assert script.wait(60) == 0, script.output() + server.output()
    lines = {line.split(':', 1)[0]: line.split(':', 1)[1].strip() for line in script.output().splitlines()
             if ':' in line}
    frame, points = lines['smoothed'].split(' ', 1)
    points = np.array(ast.literal_eval(points))
    x = np.linspace(0.2, 2.2, 40)
    zigzag = np.stack([x, 0.2 + 0.015 * (-1.0) ** np.arange(40)], axis=1)
    assert frame == 'map' and points.shape == zigzag.shape
    assert _turning(points) < 0.2 * _turning(zigzag)
    assert points[0] == pytest.approx(zigzag[0]) and points[-1] == pytest.approx(zigzag[-1])
    assert lines['through the block'] == 'None'
    assert lines['error code'] == str(SmoothPath.Result.SMOOTHED_PATH_IN_COLLISION)
    assert lines['unknown id'] == f'None {SmoothPath.Result.INVALID_SMOOTHER}'
    assert published and len(published[0].poses) == len(zigzag)
